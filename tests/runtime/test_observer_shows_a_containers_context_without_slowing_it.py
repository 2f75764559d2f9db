"""The observer interface a running container serves beside its management interface (what the
WebLab console watches in another process): a watch starts with a snapshot, then polls what
followed: monitor values, policy firings with their rules' degrees (a crisp set traced only while
watched), property changes, the calls of the operations it names (not others), the faults. The
container only appends to a bounded ring: a watcher that never polls loses the oldest events and
is told how many; a waiting poll is woken by the next event; a watch not polled expires and, none
left, the container no longer records anything. Over Pyro5 it admits whom the endpoint admits."""

from __future__ import annotations

import threading
import time
from typing import Any, ClassVar

import Pyro5.api
import Pyro5.errors
import pytest

from acordcs.descriptor import to_xml
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.connectors.remote import RemoteConnector, bytes_back, container_uri
from acordcs.runtime.errors import ConfigurationError, RemoteCallError, RemoteUnreachableError
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management_server import manage
from acordcs.runtime.live.observer import MAX_BATCH, OBSERVE_OBJECT, Observer
from acordcs.runtime.ports import sync_port
from tests.support.descriptors import (
    application,
    component,
    container,
    monitor,
    op,
    policy_set,
    port,
    prop,
    ref,
)

TOKEN = "token-of-the-house"
FRAME = bytes(range(256)) * 4


class Heater(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"level": 0, "mode": ""}
    ports = (sync_port("HeaterPort"),)

    def warm(self, level: int) -> bytes:
        self.set("level", level)
        return FRAME

    def fail(self) -> None:
        raise RuntimeError("the element burnt out")


def home():
    return application(
        "Home",
        containers=(
            container(
                "house",
                ref("component", "Heater"),
                ref("monitor", "Thermo"),
                ref("policy-set", "Comfort"),
            ),
        ),
        components=(
            component(
                "Heater",
                properties=(prop("level", 0), prop("mode", "")),
                operations=(op("warm", ("level", "int", "in")), op("fail")),
                ports=(port("HeaterPort"),),
            ),
        ),
        monitors=(monitor("Thermo", prop("temp", 20.0), feeds=("Comfort",)),),
        policy_sets=(
            policy_set(
                "Comfort",
                {"rules": ['hot: if Thermo.temp > 30 then Heater.mode = "cool"']},
                adapts=(ref("component", "Heater"),),
            ),
        ),
    )


@pytest.fixture
def served(monkeypatch):
    """The house served with its token: (running application, the observer's URI, the
    container's URI)."""
    monkeypatch.delenv("ACORDCS_TOKEN", raising=False)
    app = home()
    run = assemble(app, clock=VirtualClock(), factories={"Heater": Heater}, token=TOKEN)
    server = run.serve("house", host="127.0.0.1")
    manage(run, "house", server, to_xml(app), GivenClasses({"Heater": Heater}))
    yield (
        run,
        f"PYRO:{OBSERVE_OBJECT.format('house')}@127.0.0.1:{server.port}",
        container_uri("house", "127.0.0.1", server.port),
    )
    run.close()


def ask(uri: str, method: str, *args: Any, token: str | None = TOKEN, timeout=5.0) -> Any:
    connector = RemoteConnector(timeout=timeout, token=token)
    try:
        return connector.request(uri, method, *args, where="test")
    finally:
        connector.close()


def kinds(events: list[dict]) -> list[tuple]:
    return [(e["kind"], e["element"], e["attribute"]) for e in events]


def test_a_watch_sees_the_snapshot_then_what_followed(served):
    run, uri, house_uri = served
    house = run.container("house")
    started = ask(uri, "watch", ["Heater.warm"], True)
    snap = started["snapshot"]
    assert snap["container"] == "house" and snap["seed"] == 0 and snap["faults"] == 0
    assert snap["elements"]["Thermo"] == {"temp": 20.0}
    assert snap["elements"]["Heater"] == {"level": 0, "mode": ""}
    assert snap["policy_sets"] == {"Comfort": None}  # not fired yet
    assert house.policy_set("Comfort").trace_rules  # a watch asked for the crisp degrees

    run.clock.run_until(1.5)
    house.monitor("Thermo").update(temp=35.0)
    ask(house_uri, "call", "Heater", "HeaterPort", "warm", [3], {})
    with pytest.raises(RemoteCallError, match="burnt out"):
        ask(house_uri, "call", "Heater", "HeaterPort", "fail", [], {})
    got = ask(uri, "poll", started["watch"], started["after"], 0)
    events = got["events"]
    assert kinds(events) == [
        ("monitor.updated", "Thermo", None),
        ("property.changed", "Heater", "mode"),
        ("policy.fired", "Comfort", None),
        ("property.changed", "Heater", "level"),
        ("operation.called", "Heater", "warm"),
    ]  # fail() is not named: not seen
    assert events[0]["values"] == {"temp": 35.0} and events[0]["time"] == 1.5
    assert (
        events[1]["value"] == "cool" and events[1]["old"] == "" and events[1]["origin"] == "Comfort"
    )
    firing = events[2]["firing"]
    assert firing["set"] == "Comfort" and firing["engine"] == "clips" and firing["fires"] == 1
    assert firing["time"] == 1.5 and firing["outputs"] == {"Heater.mode": "cool"}
    assert firing["inputs"] == {"Thermo.temp": 35.0, "Heater.mode": ""}
    assert firing["rules"] == [["rules", "hot", 1.0]]
    call = events[4]
    assert call["args"] == [3] and bytes_back(call["value"]) == FRAME and call["error"] is None
    assert [e["seq"] for e in events] == sorted(e["seq"] for e in events)
    assert got["dropped"] == 0 and not got["more"] and got["time"] == 1.5
    assert [(f["kind"], f["where"]) for f in got["faults"]] == [("component", "Heater.fail")]
    assert "burnt out" in got["faults"][0]["error"]
    # Nothing new since: an empty poll, and the same cursor.
    again = ask(uri, "poll", started["watch"], got["after"], 0)
    assert again["events"] == [] and again["after"] == got["after"] and again["faults"] == []
    # The snapshot now shows the firing.
    now = ask(uri, "snapshot")
    assert now["policy_sets"]["Comfort"]["rules"] == [["rules", "hot", 1.0]]
    assert now["elements"]["Heater"] == {"level": 3, "mode": "cool"} and now["faults"] == 1
    assert ask(uri, "unwatch", started["watch"]) is True
    assert not house.policy_set("Comfort").trace_rules  # back as it was


def test_a_watch_that_names_no_operation_sees_no_call(served):
    run, uri, house_uri = served
    started = ask(uri, "watch", [], False)
    ask(house_uri, "call", "Heater", "HeaterPort", "warm", [5], {})
    events = ask(uri, "poll", started["watch"], started["after"], 0)["events"]
    assert kinds(events) == [("property.changed", "Heater", "level")]
    assert not run.container("house").policy_set("Comfort").trace_rules


def test_a_watcher_that_never_polls_loses_the_oldest_events_and_is_told():
    run = assemble(home(), clock=VirtualClock(), factories={"Heater": Heater})
    with run:
        house = run.container("house")
        observer = Observer(house, lambda: ["Comfort"], keep=100)
        started = observer.watch()
        for i in range(300):  # each: monitor.updated, then policy.fired (no rule holds)
            house.monitor("Thermo").update(temp=float(i % 30))
        got = observer.poll(started["watch"], started["after"])
        assert got["dropped"] == 500  # the ring keeps the last 100 of 600
        assert [e["values"]["temp"] for e in got["events"][::2]] == [
            float(i % 30) for i in range(250, 300)
        ]
        assert {e["kind"] for e in got["events"][1::2]} == {"policy.fired"}
        assert not got["more"]
        # More than a poll's batch at once: the rest comes with the next poll.
        big = Observer(house, lambda: ["Comfort"], keep=1000)
        started = big.watch()
        for i in range(MAX_BATCH // 2 + 5):
            house.monitor("Thermo").update(temp=float(i % 30))
        first = big.poll(started["watch"], started["after"])
        assert len(first["events"]) == MAX_BATCH and first["more"] and first["dropped"] == 0
        rest = big.poll(started["watch"], first["after"])
        assert len(rest["events"]) == 10 and not rest["more"]


def test_a_waiting_poll_is_woken_by_the_next_event():
    run = assemble(home(), clock=VirtualClock(), factories={"Heater": Heater})
    with run:
        house = run.container("house")
        observer = Observer(house, lambda: ["Comfort"])
        started = observer.watch()
        got: list[dict] = []
        poller = threading.Thread(
            target=lambda: got.append(observer.poll(started["watch"], started["after"], 2.0))
        )
        begun = time.monotonic()
        poller.start()
        while observer.waiting == 0 and time.monotonic() - begun < 2.0:
            time.sleep(0.001)  # the poll is waiting: the container's update must wake it
        house.monitor("Thermo").update(temp=25.0)
        poller.join(5.0)
        assert got and got[0]["events"][0]["values"] == {"temp": 25.0}
        assert time.monotonic() - begun < 1.9  # woken, not timed out (its wait was 2 s)


def test_an_idle_watch_expires_and_then_nothing_is_recorded():
    run = assemble(home(), clock=VirtualClock(), factories={"Heater": Heater})
    with run:
        house = run.container("house")
        observer = Observer(house, lambda: ["Comfort"], idle=0.2)
        started = observer.watch()
        house.monitor("Thermo").update(temp=21.0)
        assert observer.poll(started["watch"], started["after"])["events"]
        time.sleep(0.5)  # longer than idle: the watch is abandoned
        house.monitor("Thermo").update(temp=22.0)  # checks expiry on the container's side
        for _ in range(64):
            house.monitor("Thermo").update(temp=23.0)
        assert observer.watches == 0
        with pytest.raises(ConfigurationError, match=r"expired after 0\.2 s without a poll"):
            observer.poll(started["watch"], started["after"])
        seq = observer.watch()["after"]
        house.monitor("Thermo").update(temp=24.0)
        observer.close()
        for _ in range(10):
            house.monitor("Thermo").update(temp=25.0)  # nobody watches: not recorded
        assert observer.watch()["after"] == seq + 2  # the update watched: 2 events, then none


def test_too_many_watches_are_refused_with_what_to_do():
    run = assemble(home(), clock=VirtualClock(), factories={"Heater": Heater})
    with run:
        observer = Observer(run.container("house"), max_watches=2)
        observer.watch()
        second = observer.watch()
        with pytest.raises(ConfigurationError, match="maximum of 2 watches") as refused:
            observer.watch()
        assert "unwatch one" in str(refused.value.hint)
        observer.unwatch(second["watch"])
        observer.watch()
        with pytest.raises(ConfigurationError, match=r"as Component\.operation"):
            observer.watch(["warm"])


def test_the_observer_admits_whom_the_endpoint_admits(served):
    _run, uri, _ = served
    for wrong in (None, "guess"):
        with pytest.raises(RemoteUnreachableError, match="wrong or missing token"):
            ask(uri, "snapshot", token=wrong)
    proxy = Pyro5.api.Proxy(uri)
    proxy._pyroHandshake = TOKEN
    proxy._pyroTimeout = 3.0
    with proxy:
        proxy._pyroBind()
        assert proxy._pyroMethods == {"watch", "poll", "unwatch", "snapshot"}
        assert not proxy._pyroAttrs
    json_proxy = Pyro5.api.Proxy(uri)
    json_proxy._pyroSerializer = "json"
    json_proxy._pyroHandshake = TOKEN
    json_proxy._pyroTimeout = 3.0
    with json_proxy, pytest.raises(Pyro5.errors.SecurityError, match="serpent"):
        json_proxy.snapshot()
    with pytest.raises(RemoteCallError, match="calls is a list"):
        ask(uri, "watch", "Heater.warm", False)
    with pytest.raises(RemoteCallError, match="watch and after are integers"):
        ask(uri, "poll", "1", 0, 0)
    with pytest.raises(RemoteCallError, match="no watch 99"):
        ask(uri, "poll", 99, 0, 0)
