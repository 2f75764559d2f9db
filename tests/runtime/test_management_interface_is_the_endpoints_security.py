"""The management interface a running container serves beside its endpoint (what ``acordcs-gen
update`` calls) admits whom the endpoint admits: the application's token in the handshake, serpent
only, its methods and nothing else. Served without a token it answers ``status`` but refuses
updates and holds, unless started on a loopback host with updates allowed explicitly. It
refuses an update made against another descriptor than the one it runs, and a change that cannot apply live, and
changes nothing then; the second identical update does nothing."""

from __future__ import annotations

import re
from typing import Any

import Pyro5.api
import Pyro5.errors
import pytest

from acordcs.descriptor import to_xml
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.connectors.remote import RemoteConnector
from acordcs.runtime.errors import RemoteCallError, RemoteUnreachableError
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management import digest
from acordcs.runtime.live.management_server import MANAGE_OBJECT, manage
from tests.support.descriptors import (
    application,
    component,
    container,
    monitor,
    policy_set,
    prop,
    ref,
)

TOKEN = "token-of-the-house"
RULE = 'hot: if Thermo.temp > 30 then Heater.mode = "cool"'


def home(rule: str = RULE, *, level: int = 0, where: str = "house"):
    rooms = {"house": [ref("monitor", "Thermo"), ref("policy-set", "Comfort")], "shed": []}
    rooms[where].append(ref("component", "Heater"))
    return application(
        "Home",
        containers=(container("house", *rooms["house"]), container("shed", *rooms["shed"])),
        components=(component("Heater", properties=(prop("level", level), prop("mode", ""))),),
        monitors=(monitor("Thermo", prop("temp", 20.0), feeds=("Comfort",)),),
        policy_sets=(
            policy_set("Comfort", {"rules": [rule]}, adapts=(ref("component", "Heater"),)),
        ),
    )


@pytest.fixture
def served(monkeypatch, request):
    """The house served (token: the parameter, default TOKEN; and whether updates are allowed
    without one), with its management interface."""
    monkeypatch.delenv("ACORDCS_TOKEN", raising=False)
    token, without = getattr(request, "param", (TOKEN, False))
    app = home()
    data = to_xml(app)
    run = assemble(app, clock=VirtualClock(), only=["house"], token=token)
    server = run.serve("house", host="127.0.0.1")
    manage(run, "house", server, data, GivenClasses(), without_token=without)
    uri = f"PYRO:{MANAGE_OBJECT.format('house')}@127.0.0.1:{server.port}"
    yield run, uri, data
    run.close()


def ask(uri: str, method: str, *args: Any, token: str | None = TOKEN) -> Any:
    connector = RemoteConnector(timeout=3.0, token=token)
    try:
        return connector.request(uri, method, *args, where="test")
    finally:
        connector.close()


def test_the_token_admits_callers_and_only_its_methods_are_exposed(served):
    _, uri, data = served
    status = ask(uri, "status")
    assert status["container"] == "house" and status["digest"] == digest(data)
    assert status["refusal"] is None and status["policy_sets"]["Comfort"]["fires"] == 0
    assert ask(uri, "descriptor") == data.decode()
    for wrong in (None, "guess"):
        with pytest.raises(RemoteUnreachableError, match="wrong or missing token"):
            ask(uri, "status", token=wrong)
    proxy = Pyro5.api.Proxy(uri)
    proxy._pyroHandshake = TOKEN
    proxy._pyroTimeout = 3.0
    with proxy:
        proxy._pyroBind()
        assert proxy._pyroMethods == {
            "status",
            "descriptor",
            "properties",
            "apply",
            "set_property",
            "hold",
            "release",
        }
        assert not proxy._pyroAttrs
    with pytest.raises(AttributeError, match="no exposed attribute or method 'touched'"):
        ask(uri, "touched", "Heater", "level")


def test_another_serializer_is_refused(served):
    _, uri, _ = served
    proxy = Pyro5.api.Proxy(uri)
    proxy._pyroSerializer = "json"
    proxy._pyroHandshake = TOKEN
    proxy._pyroTimeout = 3.0
    with proxy, pytest.raises(Pyro5.errors.SecurityError, match="serpent"):
        proxy.status()


@pytest.mark.parametrize("served", [(None, False)], indirect=True)
def test_without_a_token_updates_are_refused(served):
    run, uri, data = served
    assert ask(uri, "status", token=None)["refusal"].startswith(
        "container 'house' was started without a token (ACORDCS_TOKEN): it takes no update"
    )
    reply = ask(uri, "apply", to_xml(home(level=3)).decode(), digest(data), {}, False, token=None)
    assert reply["status"] == "refused" and "without a token" in reply["error"]
    assert run.container("house").get_property("Heater", "level") == 0
    with pytest.raises(RemoteCallError, match="it takes no update and holds no call"):
        ask(uri, "hold", "Heater", 5.0, token=None)
    with pytest.raises(RemoteCallError, match="it takes no update and sets no property"):
        ask(uri, "set_property", "Heater", "level", 4, token=None)
    assert run.container("house").get_property("Heater", "level") == 0


def test_a_property_set_is_typed_by_the_model_and_must_be_the_models(served):
    run, uri, _ = served
    reply = ask(uri, "set_property", "Heater", "level", 4)
    assert (reply["value"], reply["old"]) == (4, 0)
    assert run.container("house").get_property("Heater", "level") == 4
    assert ask(uri, "status")["holds"] == []
    for element, attribute, value, said in (
        ("Heater", "level", "4", "is an int: not '4'"),
        ("Heater", "level", True, "is an int: not True"),
        ("Heater", "level", 2**64, "is an int"),
        ("Heater", "__dict__", 1, "has no property 'Heater'.'__dict__'"),
        ("Thermo", "temp", "warm", "is a double: not 'warm'"),  # a monitor's: typed too
        ("Comfort", "fires", 1, "has no property"),  # a policy set's are not the model's
    ):
        with pytest.raises(RemoteCallError, match=re.escape(said)):
            ask(uri, "set_property", element, attribute, value)
    assert run.container("house").get_property("Heater", "level") == 4


@pytest.mark.parametrize("served", [(None, True)], indirect=True)
def test_without_a_token_on_loopback_updates_are_taken_when_allowed(capsys, served):
    run, uri, data = served
    new = to_xml(home(level=3))
    reply = ask(uri, "apply", new.decode(), digest(data), {}, False, token=None)
    assert reply["status"] == "applied", reply
    assert reply["applied"] == ["~ component Heater: property level: default 0 -> 3"]
    assert run.container("house").get_property("Heater", "level") == 3
    out = capsys.readouterr().out
    assert f"house: runs descriptor sha256 {digest(data)}" in out
    assert (
        "house: t=0.000 s: model.updated: ~ component Heater: property level: default 0 -> 3" in out
    )
    assert f"house: now runs descriptor sha256 {digest(new)}" in out


def test_an_update_against_another_descriptor_or_not_live_changes_nothing(served):
    run, uri, data = served
    house = run.container("house")
    stale = ask(uri, "apply", to_xml(home(level=3)).decode(), "0" * 64, {}, False)
    assert stale["status"] == "refused" and "changed since the plan was made" in stale["error"]
    moved = ask(uri, "apply", to_xml(home(level=3, where="shed")).decode(), digest(data), {}, False)
    assert moved["status"] == "refused"
    assert moved["error"].startswith(
        "~ component Heater: container house -> shed: cannot apply live (build, then stop and "
        "start the application"
    )
    assert house.get_property("Heater", "level") == 0 and house.components()
    assert ask(uri, "status")["digest"] == digest(data) and ask(uri, "status")["updates"] == 0


def test_the_second_identical_update_does_nothing(served):
    run, uri, data = served
    new = to_xml(home(RULE.replace("> 30", "> 25")))
    first = ask(uri, "apply", new.decode(), digest(data), {}, False)
    assert first["status"] == "applied" and first["digest"] == digest(new)
    assert first["applied"] == ["~ policy set Comfort: rule hot: ... > 30 ... -> ... > 25 ..."]
    house = run.container("house")
    run.clock.run_for(2.5)
    house.monitor("Thermo").update(temp=26.0)  # the set's first firing after the update
    taken = ask(uri, "status")["last_update"]
    assert taken["fired_before"] == {"Comfort": None} and taken["applied"] == 0.0
    assert taken["first_fired"] == {"Comfort": 2.5}
    second = ask(uri, "apply", new.decode(), digest(new), {}, False)
    assert second["status"] == "unchanged" and second["applied"] == []
    assert ask(uri, "status")["updates"] == 2
    assert house.get_property("Heater", "mode") == "cool"
