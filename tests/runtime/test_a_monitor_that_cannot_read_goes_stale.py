"""A monitor that cannot read goes stale, says so, and is fresh again at its next reading
(acordcs.runtime.monitor, acordcs.runtime.acquisition): a polling monitor whose operation raises
(a call that timed out: its link is down) keeps its last values, counts a fault per tick and emits
one ``monitor.stale`` (value True, the cause, since when); an intercepting monitor with
``quiet_after`` goes stale after that many seconds without a call, its ``on_quiet`` asked what the
silence says; the next reading emits ``monitor.stale`` False (how long it was stale) before its
``monitor.updated``."""

from __future__ import annotations

from typing import Any, ClassVar

import pytest

from acordcs.runtime import events as ev
from acordcs.runtime.acquisition import InterceptingMonitor, ObservedCall, PollingMonitor
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.errors import ConfigurationError, RemoteTimeoutError
from acordcs.runtime.ports import sync_port


class Locomotion(CtxComponent):
    ports = (sync_port("LocomotionPort"),)

    def move(self, speed: float) -> float:
        return speed


class Access(CtxComponent):
    down = False

    def countUsers(self) -> int:
        if self.down:
            raise RemoteTimeoutError("countUsers() took longer than 2 s", where="AccessLink")
        return 4


class Navigator(CtxComponent):
    ports = (sync_port("Nav", role="required"),)


@pytest.fixture
def lab():
    with Container("lab", clock=VirtualClock(3)) as c:
        for cls in (Locomotion, Access, Navigator):
            c.install_factory(ComponentFactory(cls.__name__, cls))
            c.create(cls.__name__, cls.__name__)
        c.connect("Navigator.Nav", "Locomotion.LocomotionPort")
        yield c


def seen(lab: Container, monitor: str) -> list[tuple[Any, ...]]:
    """The monitor's events as (time, kind, value or values, data), in order."""
    got: list[tuple[Any, ...]] = []

    def take(event: ev.Event) -> None:
        if event.kind == ev.MONITOR_STALE:
            got.append((event.time, "stale", event.value, dict(event.data)))
        else:
            got.append((event.time, "updated", dict(event.data)))

    for kind in (ev.MONITOR_STALE, ev.MONITOR_UPDATED):
        lab.subscribe(kind, take, name=f"test:{kind}", element=monitor)
    return got


def test_a_polling_monitor_whose_call_times_out_keeps_its_values_stale_until_it_reads(lab):
    usage = PollingMonitor(
        "Usage", frequency=1.0, sources=["Access"], operation="countUsers",
        attributes={"numUsers": 1},
    )  # fmt: skip
    got = seen(lab, "Usage")
    lab.add_monitor(usage)
    lab.clock.sleep(1.0)
    lab.find("Access").instance.down = True
    lab.clock.sleep(3.0)  # three ticks fail
    assert usage.attributes == {"numUsers": 4} and usage.stale_since == 2.0
    assert lab.faults.counts["monitor"] == 3
    lab.find("Access").instance.down = False
    lab.clock.sleep(1.0)
    cause = "RemoteTimeoutError: AccessLink: error: countUsers() took longer than 2 s"
    assert got == [
        (1.0, "updated", {"numUsers": 4}),
        (2.0, "stale", True, {"cause": got[1][3]["cause"], "since": 2.0}),  # once, not per tick
        (5.0, "stale", False, {"stale_for": 3.0}),
        (5.0, "updated", {"numUsers": 4}),
    ]
    assert got[1][3]["cause"].startswith(cause[:40]), got[1][3]["cause"]
    assert usage.stale_since is None


class Control(InterceptingMonitor):
    quiet_after: ClassVar[float | None] = 2.0

    def __init__(self, name: str, **kw: Any) -> None:
        super().__init__(name, **kw)
        self.quiet: list[float] = []

    def on_call(self, call: ObservedCall) -> dict[str, object]:
        return {"speed": call.args[0]}

    def on_quiet(self, quiet_for: float) -> dict[str, object] | None:
        self.quiet.append(quiet_for)
        return {"speed": 0.0} if quiet_for >= 3.0 else None


QUIET = "no call through Locomotion.LocomotionPort for 2.0 s"


def test_an_intercepting_monitor_goes_stale_after_its_quiet_seconds_without_a_call(lab):
    control = Control("Control", sources=["Locomotion.LocomotionPort"], attributes={"speed": 1.0})
    got = seen(lab, "Control")
    lab.add_monitor(control)
    lab.clock.sleep(5.0)  # no call yet: a source not used yet is no silence
    assert got == [] and control.quiet == []
    nav = lab.find("Navigator").instance.port("Nav")
    nav.call("move", 100.0)  # t=5
    lab.clock.sleep(3.5)  # heard every 0.5 s: quiet from t=7
    assert control.quiet == [2.0, 2.5, 3.0, 3.5]
    nav.call("move", 120.0)  # t=8.5
    assert got == [
        (5.0, "updated", {"speed": 100.0}),
        (7.0, "stale", True, {"cause": QUIET, "since": 7.0}),
        (8.0, "updated", {"speed": 0.0}),  # what the silence says, still stale
        (8.5, "updated", {"speed": 0.0}),
        (8.5, "stale", False, {"stale_for": 1.5}),
        (8.5, "updated", {"speed": 120.0}),
    ]


def test_quiet_after_must_be_positive(lab):
    class Never(InterceptingMonitor):
        quiet_after = 0.0

    with pytest.raises(ConfigurationError, match="quiet_after must be > 0 s"):
        lab.add_monitor(Never("Never", sources=["Locomotion.LocomotionPort"]))
