"""The access link against its arithmetic, and the profiles' cycle rates in order."""

from __future__ import annotations

import pytest
from weblab_sim import experiment, network

from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.ports import PortSpec


class Server(CtxComponent):
    ports = (PortSpec("api", "synchronous", "provided"), PortSpec("feed", "stream", "provided"))

    def echo(self, data):
        return data


class Client(CtxComponent):
    ports = (PortSpec("api", "synchronous", "required"), PortSpec("feed", "stream", "required"))


def linked(qos: dict[str, object]) -> tuple[VirtualClock, network.AccessLink, object, object]:
    clock = VirtualClock(0)
    box = Container("box", clock=clock)
    box.install_factory(ComponentFactory("Server", Server))
    box.install_factory(ComponentFactory("Client", Client))
    server = box.create("Server", "server")
    client = box.create("Client", "client")
    link = network.AccessLink(clock)
    box.connect("client.api", "server.api", connector=link, qos=dict(qos))
    box.connect("client.feed", "server.feed", connector=link, qos=dict(qos))
    return clock, link, server, client


def test_a_call_takes_both_latencies_and_both_transmissions() -> None:
    clock, _, _, client = linked({"latency": 0.1, "jitter": 0.0, "bandwidth": 1e6})
    payload = b"x" * 12_500  # 0.1 s at 1 Mbit/s each way (the request carries it too, serialised)
    client.port("api").call("echo", payload)
    request = network.size_of(["echo", [payload], {}])
    expected = 0.1 + request * 8 / 1e6 + 0.1 + len(payload) * 8 / 1e6
    assert clock.now() == pytest.approx(expected, rel=1e-9)


def test_a_full_downlink_drops_stream_frames_and_delays_replies() -> None:
    clock, link, server, client = linked({"latency": 0.0, "jitter": 0.0, "bandwidth": 1e6})
    for _ in range(10):  # 10 x 10 KB at once: 4 fit in the 48 KB buffer, the rest is dropped
        server.port("feed").push({"frame": 1}, size=10_000)
    assert link.dropped_frames == 10 - network.BUFFER_BYTES // 10_000
    client.port("api").call("echo", b"")
    # The reply waits behind the 4 buffered frames: 4 x 10 KB at 1 Mbit/s.
    assert clock.now() == pytest.approx(4 * 10_000 * 8 / 1e6, abs=0.001)


def test_unknown_profile_is_refused_with_the_known_ones() -> None:
    with pytest.raises(ValueError, match="residential"):
        network.profile("satellite")


def test_cycle_rates_rise_from_residential_to_campus_to_lan(weblab_app: None) -> None:
    rates = [
        experiment.run(name, 0, "adaptive", time_cap=15.0)["cycles_per_s"]
        for name in ("residential", "campus", "LAN")
    ]
    assert rates[0] < rates[1] < rates[2]
