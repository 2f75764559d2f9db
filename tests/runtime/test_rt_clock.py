"""Clocks: virtual-time scheduling, determinism for a seed, the real-time scheduler, and the shaping
connector that delays through the clock."""

from __future__ import annotations

import threading

import pytest

from acordcs.runtime.clock import RealClock, VirtualClock
from acordcs.runtime.component import ComponentFactory
from acordcs.runtime.connectors.shaping import ShapedConnector
from acordcs.runtime.container import Container
from acordcs.runtime.errors import ConnectorError
from acordcs.runtime.monitor import Monitor
from tests.support.components import Camera, Client, Counter, Receiver, Screen, Sender


def test_virtual_clock_runs_events_in_time_then_fifo_order():
    clock = VirtualClock()
    order = []
    clock.call_at(2.0, lambda: order.append("b"))
    clock.call_at(1.0, lambda: order.append("a"))
    clock.call_at(2.0, lambda: order.append("c"))
    cancelled = clock.call_at(1.5, lambda: order.append("x"))
    cancelled.cancel()
    clock.run_until(1.9)
    assert order == ["a"]
    assert clock.now() == 1.9
    clock.run()
    assert order == ["a", "b", "c"]
    assert clock.now() == 2.0


def test_virtual_periodic_timer_keeps_a_fixed_rate_and_sleep_lets_time_pass():
    clock = VirtualClock()
    ticks = []
    timer = clock.call_every(0.25, lambda: ticks.append(clock.now()))
    clock.sleep(1.0)  # a sleeping caller: events in the window run meanwhile
    assert ticks == [0.25, 0.5, 0.75, 1.0]
    timer.cancel()
    clock.run_for(10)
    assert len(ticks) == 4
    with pytest.raises(ValueError, match="period must be > 0"):
        clock.call_every(0, lambda: None)
    with pytest.raises(ValueError, match="delay must be >= 0"):
        clock.call_later(-1, lambda: None)


def test_raising_timer_callback_does_not_stop_the_clock():
    clock = VirtualClock()
    errors, ticks = [], []
    clock.on_error = lambda timer, exc: errors.append(str(exc))

    def tick():
        ticks.append(clock.now())
        raise RuntimeError("tick failed")

    clock.call_every(1.0, tick)
    clock.run_for(3.0)
    assert len(ticks) == 3
    assert errors == ["tick failed"] * 3


def test_rng_streams_are_per_purpose_and_reproducible():
    a, b = VirtualClock(seed=5), VirtualClock(seed=5)
    a.rng("x").random(100)  # drawing from one stream does not shift another
    assert a.rng("y").random() == b.rng("y").random()
    assert VirtualClock(seed=6).rng("y").random() != VirtualClock(seed=5).rng("y").random()


def _scenario(seed: int) -> list[tuple[float, int]]:
    clock = VirtualClock(seed=seed)
    arrivals: list[tuple[float, int]] = []

    class Recording(Screen):
        def on_video(self, item):
            arrivals.append((round(self.clock.now(), 9), item["frame"]))

    class Noise(Monitor):
        def acquire(self):
            return {"level": float(self.container.clock.rng("noise").random())}

    with Container("sim", clock=clock) as c:
        c.install_factory(ComponentFactory("Camera", Camera))
        c.install_factory(ComponentFactory("Screen", Recording))
        c.create("Camera", "cam")
        c.create("Screen", "scr")
        c.add_monitor(Noise("noise", frequency=5.0, attributes={"level": 0.0}))
        link = ShapedConnector(clock, latency=0.05, jitter=0.04, bandwidth=8_000, loss=0.2)
        c.connect("scr.video", "cam.video", connector=link, name="wan")
        clock.run_for(3.0)
        arrivals.append((-1.0, round(c.get_property("noise", "level") * 1e6)))
    return arrivals


def test_virtual_clock_run_is_deterministic_for_a_seed():
    first, again, other = _scenario(11), _scenario(11), _scenario(12)
    assert first == again
    assert first != other
    frames = [f for t, f in first if t >= 0]
    assert 0 < len(frames) < 30  # some of the 30 frames were lost (loss 0.2)
    times = [t for t, _ in first if t >= 0]
    assert times == sorted(times)  # the link is FIFO despite jitter


def test_shaped_link_delays_by_latency_and_bandwidth():
    clock = VirtualClock()
    with Container("c", clock=clock) as c:
        c.install_factory(ComponentFactory("Sender", Sender))
        c.install_factory(ComponentFactory("Receiver", Receiver))
        c.create("Sender", "s")
        r = c.create("Receiver", "r")
        c.connect(
            "s.out", "r.inbox", connector=ShapedConnector(clock, latency=0.1, bandwidth=8_000)
        )
        c.find("s").send("x" * 100)  # 100 bytes at 8 kbit/s: 0.1 s on the wire, + 0.1 s latency
        clock.run_until(0.199)
        assert r.instance.got == []
        clock.run_until(0.2)
        assert r.instance.got == ["x" * 100]
        # A policy lowering the bandwidth applies to the next message.
        c.set_property("s.out->r.inbox", "bandwidth", 800)
        c.find("s").send("y" * 100)
        clock.run_until(1.299)
        assert len(r.instance.got) == 1
        clock.run_until(1.3)
        assert len(r.instance.got) == 2


def test_shaped_sync_call_takes_round_trip_time_and_loss_times_out():
    clock = VirtualClock(seed=2)
    with Container("c", clock=clock) as c:
        c.install_factory(ComponentFactory("Counter", Counter))
        c.install_factory(ComponentFactory("Client", Client))
        c.create("Counter", "srv")
        cli = c.create("Client", "cli")
        conn = c.connect(
            "cli.api", "srv.api", connector=ShapedConnector(clock, latency=0.02, timeout=0.5)
        )
        assert cli.use() == 1
        assert clock.now() == pytest.approx(0.04)
        c.set_property(conn.name, "loss", 1.0)
        with pytest.raises(ConnectorError, match=r"timed out after 0.5 s: the request was lost"):
            cli.use()
        assert clock.now() == pytest.approx(0.54)
        with pytest.raises(ConnectorError, match="'loss' must be a probability"):
            c.set_property(conn.name, "loss", 2.0)
            cli.use()


def test_real_clock_runs_callbacks_on_its_thread_and_closes():
    clock = RealClock()
    try:
        done = threading.Event()
        errors = []
        clock.on_error = lambda timer, exc: errors.append(exc)
        clock.call_later(0.01, lambda: 1 / 0)
        clock.call_later(0.02, done.set)
        assert done.wait(5)
        assert len(errors) == 1
        ticks = []
        three = threading.Event()

        def tick():
            ticks.append(clock.now())
            if len(ticks) == 3:
                three.set()

        timer = clock.call_every(0.005, tick)
        assert three.wait(5)
        timer.cancel()
        assert ticks[:3] == sorted(ticks[:3])
        assert clock.now() > 0
    finally:
        clock.close()
    assert not clock._thread.is_alive()
