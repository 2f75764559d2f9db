"""Updates applied to the WebLab while the robot drives, in one process on a virtual clock (the
experiment's rig, residential network: the control loop runs about once a second, so the rules
for a *small* cycle rate decide): each container's management interface takes the new descriptor
as ``acordcs-gen update`` sends it. The rule for narrow turns from slow to fast: the first firing
after the update gives what the new rules give (a dense evaluation of them, independent of the
engine) and the robot goes faster, with its distance and retries untouched; a monitor added and
removed; property defaults (one changed at run time kept, then set with ``reset``); a component
added and connected, then removed; a change that cannot apply live refused by both containers; a
failing step rolled back."""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import Any, ClassVar

import pytest

from acordcs.descriptor import from_xml, to_xml
from acordcs.descriptor.diff import diff
from acordcs.engines.fuzzy import MAMDANI
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from acordcs.runtime import events as ev
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.live.apply_update import GivenClasses, container_order
from acordcs.runtime.live.management import Management
from tests.samples.weblab.conftest import APP_DIR
from tests.support import weblab_models as models
from tests.support.fuzzy_oracle import oracle

SLOW = "smallNarrow: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is slow"
FAST = SLOW.replace("is slow", "is fast")


class Broken(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"level": 0}

    def __init__(self) -> None:
        raise RuntimeError("its driver is missing")


class Session:
    """The rig, each container managed as the launcher manages it, and updates as the CLI sends
    them (in the containers' order)."""

    def __init__(self, rig: Any, tmp: Path) -> None:
        self.rig, self.tmp = rig, tmp
        registry = importlib.import_module("weblab_app.registry")
        self.classes = GivenClasses(
            {**registry.FACTORIES, "Broken": Broken}, dict(registry.MONITORS)
        )
        data = (APP_DIR / "weblab_app" / "descriptor.xml").read_bytes()
        self.managed = {
            name: Management(rig.app, name, data, classes=self.classes)
            for name in ("UserSide", "WebLabSide")
        }
        self.events: list[str] = []
        for name in self.managed:
            rig.app.container(name).subscribe(
                ev.MODEL_UPDATED, lambda e: self.events.append(e.value), name="test"
            )

    def update(self, *edits: models.Edit, reset: bool = False) -> dict[str, dict]:
        path = models.write_weblab(self.tmp / f"edited-{len(self.events)}.xmi", *edits)
        data = to_xml(describe(read_model(str(path)).architecture))
        new = from_xml(data)
        plan = diff(self.rig.app.descriptor, new)
        replies: dict[str, dict] = {}
        for name in container_order(new, list(self.managed), plan.changes):
            managed = self.managed[name]
            replies[name] = managed.apply(data.decode(), managed.digest, {}, reset)
            if replies[name]["status"] not in ("applied", "unchanged"):
                break  # as acordcs-gen update: the containers after it are not updated
        return replies

    def drive(self, seconds: float) -> None:
        nav, clock = self.rig.navigator.instance, self.rig.clock
        until = clock.now() + seconds
        while clock.now() < until:
            nav.step()


@pytest.fixture
def session(weblab_app: None, tmp_path: Path):
    from weblab_sim import experiment

    with experiment.rig("residential", 3) as rig:
        yield Session(rig, tmp_path)


def speed_rules(app) -> tuple[dict, list[str]]:
    (ps,) = [p for p in app.policy_sets if p.name == "SpeedLimiting"]
    written = {"Control.cycleRate": "cycleRate", "Control.angle": "angle"}
    variables = {
        written.get(v.name, v.name): (v.minimum, v.maximum, v.terms_text) for v in ps.variables
    }
    return variables, [r.text for r in ps.rules()]


def test_a_rule_change_applies_at_the_next_firing_and_the_robot_speeds_up(session):
    rig, lab = session.rig, session.rig.lab
    speed_limiting = rig.weblab.policy_set("SpeedLimiting")
    session.drive(10.0)  # on the first straight: narrow turns, at about 70 mm/s (slow)
    before = (lab.robot.distance, rig.recovery.get("retries"), rig.recovery.get("recoveries"))
    speed_before = lab.robot.speed()
    assert 50 < speed_before < 90
    start, fires = rig.clock.now(), speed_limiting.fires
    replies = session.update(models.rule(SLOW, FAST))
    line = "~ policy set SpeedLimiting: rule smallNarrow: ... is slow -> ... is fast"
    assert replies["WebLabSide"]["status"] == "applied" and replies["WebLabSide"]["applied"] == [
        line
    ]
    assert replies["UserSide"]["status"] == "unchanged"
    assert session.events == [line]
    # the update itself moved nothing and reset nothing
    after = (lab.robot.distance, rig.recovery.get("retries"), rig.recovery.get("recoveries"))
    assert after == before and rig.clock.now() == start
    # the first firing after it runs the new rules
    while speed_limiting.fires == fires:
        rig.navigator.instance.step()
    firing = speed_limiting.last_firing
    variables, rules = speed_rules(rig.app.descriptor)
    inputs = {
        "cycleRate": firing.inputs["Control.cycleRate"],
        "angle": firing.inputs["Control.angle"],
    }
    want = oracle(variables, rules, inputs, "Locomotion.maxSpeed", MAMDANI)
    assert firing.outputs["Locomotion.maxSpeed"] == pytest.approx(want, abs=1e-6)
    # ... where the old ones would have said otherwise (the rule decides here)
    _, old_rules = speed_rules(from_xml((APP_DIR / "weblab_app" / "descriptor.xml").read_bytes()))
    assert oracle(variables, old_rules, inputs, "Locomotion.maxSpeed", MAMDANI) < want - 20
    # and the robot drives faster than it did before the update (the straight goes on)
    session.drive(6.0)
    sped = (lab.robot.distance - after[0]) / (rig.clock.now() - start)
    assert sped > 1.5 * speed_before
    assert rig.weblab.faults.counts["total"] == 0


def test_a_monitor_added_runs_and_removed_stops(session):
    replies = session.update(models.sessions_monitor)
    assert replies["WebLabSide"]["applied"] == [
        "+ monitor Sessions: in container WebLabSide",
        "~ policy set BandwidthLimiting: fed by Control, Usage -> Control, Sessions, Usage",
    ]
    weblab = session.rig.weblab
    session.drive(3.0)
    sessions = weblab.monitor("Sessions")
    assert sessions.ticks >= 5 and weblab.policy_set("BandwidthLimiting").fed_by[1] == "Sessions"
    replies = session.update()
    assert replies["WebLabSide"]["applied"][0] == "- monitor Sessions"
    assert "Sessions" not in weblab.monitors() and sessions.container is None
    ticks = sessions.ticks
    session.drive(2.0)
    assert sessions.ticks == ticks and weblab.faults.counts["total"] == 0


def test_defaults_apply_where_never_changed_at_run_time(session):
    edits = (
        models.default("Navigator", "lookAhead", "350"),
        models.default("Navigator", "forwardSpeed", "120"),
        models.default("Recovery", "waitTime", "2"),
    )
    replies = session.update(*edits)
    assert replies["UserSide"]["applied"] == [
        "~ component Navigator: property lookAhead: default 300 -> 350"
    ]
    # the rig set the speed the Navigator asks for: changed at run time, kept
    assert replies["UserSide"]["kept"] == [
        "~ component Navigator: property forwardSpeed: default 100 -> 120: kept at 200, changed "
        "at run time (--reset sets the new default)"
    ]
    assert replies["WebLabSide"]["applied"] == [
        "~ component Recovery: property waitTime: default 3 -> 2"
    ]
    nav = session.rig.navigator
    assert (nav.get("lookAhead"), nav.get("forwardSpeed")) == (350.0, 200.0)
    assert session.rig.recovery.get("waitTime") == 2.0
    session.update(*edits, reset=True)  # nothing left to do: the descriptor is the same
    assert nav.get("forwardSpeed") == 200.0
    session.update()  # back to the sample's defaults, then the new ones with reset
    replies = session.update(*edits, reset=True)
    assert nav.get("forwardSpeed") == 120.0
    assert replies["UserSide"]["kept"] == []


def test_a_component_added_is_connected_then_removed_cleanly(session):
    replies = session.update(models.logger_component)
    assert replies["WebLabSide"]["applied"] == [
        "+ component Logger: in container WebLabSide",
        "+ connection LoggerLink: Logger.LoggerLocomotionPort -> Locomotion.LocomotionPort "
        "(inprocess)",
    ]
    weblab = session.rig.weblab
    logger = weblab.find("Logger")
    odometry = logger.port("LoggerLocomotionPort").call("odometry")
    assert '"distance"' in odometry  # through the new connection, to the running Locomotion
    replies = session.update()
    assert replies["WebLabSide"]["applied"] == [  # in the order applied: its connection first
        "- connection LoggerLink",
        "- component Logger",
    ]
    assert not logger.alive and "Logger" not in weblab.factories()
    assert "LoggerLink" not in [c.name for c in weblab.connections()]


def test_a_change_that_cannot_apply_live_changes_nothing(session):
    digests = {n: m.digest for n, m in session.managed.items()}
    replies = session.update(models.vision_moved)
    for reply in replies.values():
        assert reply["status"] == "refused", reply
        assert reply["error"].startswith(
            "~ component Vision: container WebLabSide -> UserSide: cannot apply live"
        )
    assert {n: m.digest for n, m in session.managed.items()} == digests
    assert session.rig.weblab.find("Vision").alive and session.events == []


def test_a_step_that_fails_rolls_its_container_back(session):
    weblab = session.rig.weblab
    telemetry = weblab.monitor("Telemetry")
    before = session.managed["WebLabSide"].digest
    replies = session.update(models.broken_component, models.without_telemetry)
    reply = replies["WebLabSide"]
    assert reply["status"] == "rolled back"
    assert reply["error"].startswith("+ component Broken: in container WebLabSide: ")
    assert "its driver is missing" in reply["error"]
    assert reply["rolled_back"] == ["- monitor Telemetry"] and reply["unrolled"] == []
    # the container with changes went first, and its failure stopped the update there
    assert list(replies) == ["WebLabSide"]
    assert session.managed["WebLabSide"].digest == session.managed["UserSide"].digest == before
    # the monitor is back, as it was: the robot's telemetry reaches it again
    assert weblab.monitor("Telemetry") is telemetry and telemetry.container is weblab
    readings = dict(telemetry.attributes)
    session.drive(3.0)
    assert telemetry.attributes != readings
    assert session.events == []
