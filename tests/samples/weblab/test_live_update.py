"""``acordcs-gen update`` on the live WebLab: the generated application started by its scripts as two
processes on loopback in real time (as ``make live`` runs it), the robot driving, then changed by
the command as a user runs it, with the scripts' environment.

On loopback the control loop runs three times a second: the cycle rate is *large*, and the rule
for narrow turns there is ``largeNarrow``. The application starts from the WebLab with that rule
at ``slow`` and is updated to the sample's ``fast``: the first firing of SpeedLimiting after the
update gives what the new rules give (a dense evaluation of them, independent of the engine) and
the robot goes faster, no process restarted, its distance, battery and retries carried on. Then,
each from the sample and back to it: a monitor added then removed; property defaults (one
changed at run time kept, then set with ``--reset``); a component added and connected; a change
that cannot apply live (exit 1, the directory and the containers unchanged); a step that fails
in the WebLab's container (its new component's class raises), which rolls that container back.
The same in one process: ``test_update_in_one_process.py``."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from acordcs.descriptor import from_xml
from acordcs.engines.fuzzy import MAMDANI
from acordcs.runtime.connectors.remote import RemoteConnector, container_uri
from acordcs.runtime.live.management_server import MANAGE_OBJECT
from tests.generator.test_shell_scripts_parse_quote_and_run import free_ports
from tests.samples.weblab.conftest import APP_DIR, SAMPLE_DIR
from tests.samples.weblab.test_live_mode import alive
from tests.samples.weblab.test_update_in_one_process import speed_rules
from tests.support import weblab_models as models
from tests.support.fuzzy_oracle import oracle
from tests.support.generator import snapshot
from tests.support.toolchain import ROOT, CliResult, entry_point, run_main

SLOW = "largeNarrow: if cycleRate is large and angle is narrow then Locomotion.maxSpeed is slow"
FAST = SLOW.replace("is slow", "is fast")
LINE = "~ policy set SpeedLimiting: rule largeNarrow: ... is slow -> ... is fast"
BROKEN = '''"""Component Broken: its driver is missing (a test's fault)."""

from weblab_app.base.Broken import BrokenBase


class Broken(BrokenBase):
    def __init__(self) -> None:
        raise RuntimeError("the driver of Broken is missing")
'''


class Live:
    """The running WebLab: its directory, the scripts' environment, the token."""

    def __init__(self, root: Path) -> None:
        self.root, self.app, self.run = root, root / "app", root / "run"
        user, lab = free_ports(2)
        self.ports = {"UserSide": user, "WebLabSide": lab}
        self.env = {
            **os.environ,
            "PYTHON": sys.executable,
            "PYTHONPATH": os.pathsep.join([str(SAMPLE_DIR), str(ROOT / "src")]),
            "ACORDCS_RUN_DIR": str(self.run),
            "ACORDCS_CLOCK": "real",
            "ACORDCS_UserSide_HOST": "127.0.0.1",
            "ACORDCS_WebLabSide_HOST": "127.0.0.1",
            "ACORDCS_UserSide_PORT": str(user),
            "ACORDCS_WebLabSide_PORT": str(lab),
            "ACORDCS_UserSide_RUN": "Navigator.run",
            "ACORDCS_TIMEOUT": "30",
            "ACORDCS_STOP_TIMEOUT": "5",
            "WEBLAB_TIME_CAP": "300",
            "WEBLAB_FORWARD_SPEED": "200",
        }
        self.env.pop("ACORDCS_TOKEN", None)
        self.token = ""

    def model(self, *edits: models.Edit) -> Path:
        """The WebLab model with ``edits``, as ``weblab.xmi`` (the name the build recorded)."""
        folder = self.root / f"model-{len(list(self.root.glob('model-*')))}"
        folder.mkdir()
        return models.write_weblab(folder / "weblab.xmi", *edits)

    def update(self, model: Path, *options: str, process: bool = False) -> CliResult:
        """``acordcs-gen update MODEL -o APP`` with the scripts' environment: the installed
        command (``process``), else the same in this process (quicker: the toolchain is
        imported already)."""
        args = ["update", str(model), "-o", str(self.app), *options]
        if process:
            done = subprocess.run([*entry_point(), *args], env=self.env, capture_output=True,
                                  text=True, timeout=120, check=False)  # fmt: skip
            return CliResult(done.returncode, done.stdout, done.stderr)
        saved = dict(os.environ)
        os.environ.clear()
        os.environ.update(self.env)
        try:
            return run_main(args)
        finally:
            os.environ.clear()
            os.environ.update(saved)

    def ask(self, container: str, method: str, *args: Any) -> Any:
        uri = f"PYRO:{MANAGE_OBJECT.format(container)}@127.0.0.1:{self.ports[container]}"
        connector = RemoteConnector(timeout=10.0, token=self.token)
        try:
            return connector.request(uri, method, *args, where=f"test: {container}")
        finally:
            connector.close()

    def odometry(self) -> dict[str, Any]:
        uri = container_uri("WebLabSide", "127.0.0.1", self.ports["WebLabSide"])
        connector = RemoteConnector(timeout=10.0, token=self.token)
        try:
            reply = connector.request(uri, "call", "Locomotion", "LocomotionPort", "odometry",
                                      [], {}, where="test")  # fmt: skip
        finally:
            connector.close()
        return dict(json.loads(reply))

    def pids(self) -> dict[str, int]:
        return {n: int((self.run / f"{n}.pid").read_text()) for n in self.ports}

    def digests(self) -> dict[str, str]:
        return {n: self.ask(n, "status")["digest"] for n in self.ports}

    def until(self, what: str, check, timeout: float = 30.0) -> Any:
        deadline = time.monotonic() + timeout
        while True:
            found = check()
            if found:
                return found
            assert time.monotonic() < deadline, f"not within {timeout:g} s: {what}"
            time.sleep(0.05)


@pytest.fixture(scope="module")
def live(weblab_app: None, tmp_path_factory) -> Iterator[Live]:
    lab = Live(tmp_path_factory.mktemp("live-update"))
    shutil.copytree(APP_DIR, lab.app, ignore=shutil.ignore_patterns("run", "__pycache__"))
    lab.run.mkdir(mode=0o700)
    start = lab.model(models.rule(FAST, SLOW))
    built = subprocess.run([*entry_point(), "build", "-q", str(start), "-o", str(lab.app)],
                           capture_output=True, text=True, check=False)  # fmt: skip
    assert built.returncode == 0, built.stdout + built.stderr
    started = subprocess.run(["sh", str(lab.app / "bin" / "start-all")], env=lab.env,
                             capture_output=True, text=True, timeout=120, check=False)  # fmt: skip
    try:
        assert started.returncode == 0, started.stdout + started.stderr
        lab.token = (lab.run / "token").read_text().strip()
        yield lab
    finally:
        subprocess.run(["sh", str(lab.app / "bin" / "stop-all")], env=lab.env,
                       capture_output=True, timeout=60, check=False)  # fmt: skip
        for name in lab.ports:
            pidfile = lab.run / f"{name}.pid"
            if pidfile.exists() and alive(pid := int(pidfile.read_text() or 0)):
                os.kill(pid, signal.SIGKILL)


def test_a_rule_change_applies_while_the_robot_drives(live: Live):
    lab_fires = lambda: live.ask("WebLabSide", "status")["policy_sets"]["SpeedLimiting"]  # noqa: E731
    live.until(
        "the robot drives", lambda: live.odometry()["distance"] > 150 and lab_fires()["fires"] > 3
    )
    pids = live.pids()
    t0, before = time.monotonic(), live.odometry()["distance"]
    time.sleep(1.5)
    speed_before = (live.odometry()["distance"] - before) / (time.monotonic() - t0)
    kept = live.ask("WebLabSide", "properties", ["Recovery", "Telemetry"])
    distance = live.odometry()["distance"]
    done = live.update(SAMPLE_DIR / "weblab.xmi", process=True)
    assert done.code == 0, done.out + done.err
    assert f"plan: 1 change\n{LINE}\n" in done.out
    assert "WebLabSide: applied 1 change in " in done.out
    assert "UserSide: nothing to change; runs descriptor " in done.out
    fires = lab_fires()["fires"]
    # no process restarted, the run carries on from where it was
    assert live.pids() == pids and all(alive(p) for p in pids.values())
    assert live.odometry()["distance"] >= distance
    now = live.ask("WebLabSide", "properties", ["Recovery", "Telemetry"])
    assert now["Recovery"] == kept["Recovery"]  # retries and recoveries
    # the battery goes on as it was (its readings are noisy), not back to the model's default 0
    assert now["Telemetry"]["batteryVoltage"] == pytest.approx(
        kept["Telemetry"]["batteryVoltage"], abs=0.1
    )
    # the first firing after the update, and the next ones, run the new rules
    variables, new_rules = speed_rules(
        from_xml((live.app / "weblab_app" / "descriptor.xml").read_bytes())
    )
    old_rules = [r.replace(" is fast", " is slow") if r.startswith("if cycleRate is large and angle is narrow") else r for r in new_rules]  # fmt: skip
    seen = 0
    differs = False
    t1, after = time.monotonic(), live.odometry()["distance"]
    while seen < 3 or not differs:
        last = fires
        firing = live.until(
            "SpeedLimiting fires", lambda last=last: (f := lab_fires())["fires"] > last and f
        )
        fires = firing["fires"]
        seen += 1
        inputs = {"cycleRate": firing["inputs"]["Control.cycleRate"],
                  "angle": firing["inputs"]["Control.angle"]}  # fmt: skip
        want = oracle(variables, new_rules, inputs, "Locomotion.maxSpeed", MAMDANI)
        assert firing["outputs"]["Locomotion.maxSpeed"] == pytest.approx(want, abs=1e-6)
        differs = (
            differs
            or want > oracle(variables, old_rules, inputs, "Locomotion.maxSpeed", MAMDANI) + 40
        )
        assert seen < 60, "no firing on a narrow turn at a large cycle rate"
    # and the robot goes faster than it did before the update
    speed_after = (live.odometry()["distance"] - after) / (time.monotonic() - t1)
    assert speed_after > 1.3 * speed_before, (speed_before, speed_after)
    log = (live.run / "WebLabSide.log").read_text()
    assert f"model.updated: {LINE}" in log and log.count("serving at") == 1
    assert live.update(SAMPLE_DIR / "weblab.xmi").out.endswith(
        "UserSide: runs descriptor {0} already: nothing to do\nWebLabSide: runs descriptor {0} "
        "already: nothing to do\n".format(live.digests()["UserSide"][:12])
    )


def test_a_monitor_added_then_removed(live: Live):
    done = live.update(live.model(models.sessions_monitor))
    assert done.code == 0, done.out + done.err
    assert "+ monitor Sessions: in container WebLabSide\n" in done.out
    live.until("Sessions polls", lambda: live.ask("WebLabSide", "properties", ["Sessions"]).get("Sessions", {}).get("sessions", 0) >= 1)  # fmt: skip
    done = live.update(SAMPLE_DIR / "weblab.xmi")
    assert done.code == 0 and "- monitor Sessions\n" in done.out, done.out + done.err
    assert live.ask("WebLabSide", "properties", ["Sessions"]) == {}


def test_property_defaults_apply_where_not_changed_at_run_time(live: Live):
    edited = live.model(
        models.default("Navigator", "lookAhead", "350"),
        models.default("Navigator", "forwardSpeed", "120"),
    )
    done = live.update(edited)
    assert done.code == 0, done.out + done.err
    assert "UserSide: applied 1 change in " in done.out
    # Navigator.run set the speed it drives at (WEBLAB_FORWARD_SPEED): changed at run time
    assert (
        "UserSide: ~ component Navigator: property forwardSpeed: default 100 -> 120: kept at 200, "
        "changed at run time (--reset sets the new default)\n"
    ) in done.out
    nav = live.ask("UserSide", "properties", ["Navigator"])["Navigator"]
    assert (nav["lookAhead"], nav["forwardSpeed"]) == (350.0, 200.0)
    assert live.update(SAMPLE_DIR / "weblab.xmi").code == 0
    done = live.update(edited, "--reset")
    assert done.code == 0 and "UserSide: applied 2 changes in " in done.out, done.out
    nav = live.ask("UserSide", "properties", ["Navigator"])["Navigator"]
    assert (nav["lookAhead"], nav["forwardSpeed"]) == (350.0, 120.0)
    assert live.update(SAMPLE_DIR / "weblab.xmi", "--reset").code == 0


def test_a_component_added_and_connected(live: Live):
    done = live.update(live.model(models.logger_component))
    assert done.code == 0, done.out + done.err
    assert (
        "+ component Logger: in container WebLabSide\n+ connection LoggerLink: "
        "Logger.LoggerLocomotionPort -> Locomotion.LocomotionPort (inprocess)\n"
    ) in done.out
    found = live.ask("WebLabSide", "properties", ["Logger", "LoggerLink"])
    assert found == {"Logger": {"lines": 0}, "LoggerLink": {}}
    done = live.update(SAMPLE_DIR / "weblab.xmi")
    assert done.code == 0 and "- component Logger\n" in done.out
    assert live.ask("WebLabSide", "properties", ["Logger", "LoggerLink"]) == {}


def test_a_change_that_cannot_apply_live_exits_1_and_changes_nothing(live: Live):
    digests, files = live.digests(), snapshot(live.app)
    done = live.update(live.model(models.vision_moved))
    assert done.code == 1, done.out + done.err
    assert "~ component Vision: container WebLabSide -> UserSide   [cannot apply live]" in done.out
    assert (
        "acordcs-gen update: ~ component Vision: container WebLabSide -> UserSide: cannot apply "
        "live: build, then stop and start the application"
    ) in done.err
    assert "acordcs-gen update: nothing changed" in done.err
    assert live.digests() == digests and snapshot(live.app) == files


def test_a_failing_step_rolls_its_container_back(live: Live):
    (live.app / "weblab_app" / "components" / "Broken.py").write_text(BROKEN, encoding="utf-8")
    digests = live.digests()
    done = live.update(live.model(models.broken_component, models.without_telemetry))
    assert done.code == 1, done.out + done.err
    assert (
        "WebLabSide: failed: + component Broken: in container WebLabSide: factory 'Broken' "
        "failed to create 'Broken': RuntimeError: the driver of Broken is missing"
    ) in done.err
    assert "WebLabSide: rolled back: - monitor Telemetry\n" in done.err
    assert "UserSide: not updated (a container before it failed)" in done.out
    assert live.digests() == digests
    telemetry = live.ask("WebLabSide", "properties", ["Telemetry"])["Telemetry"]
    assert telemetry["batteryVoltage"] > 0
    done = live.update(SAMPLE_DIR / "weblab.xmi")
    assert done.code == 0 and "plan: 0 changes" in done.out, done.out + done.err
