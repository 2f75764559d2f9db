"""The ``shell`` target's scripts: ``sh -n`` parses every one of both samples, shellcheck finds
nothing (service test: ``make test`` installs shellcheck), model strings are quoted (hostile
hosts, ids and documentation reach the program as data and never run), and the WebLab's scripts
start both containers as two processes, which serve the endpoints the other is given, call each
other over the remote connector (with user code in the user classes) while a policy adapts,
report them running, refuse a second start, and stop them."""

from __future__ import annotations

import dataclasses
import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from acordcs.codegen.targets.shell import needs, quote, shell
from tests.support.codegen import build, context
from tests.support.toolchain import SMARTROOM, WEBLAB

SRC = Path(__file__).resolve().parents[2] / "src"


def scripts(out: Path) -> list[Path]:
    found = sorted(p for p in (out / "bin").iterdir() if not p.name.endswith(".lost"))
    assert found
    return found


@pytest.fixture(scope="module", params=[WEBLAB, SMARTROOM], ids=["weblab", "smartroom"])
def built(request, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("shell") / "out"
    result = build(request.param, out, "-t", "python,shell")
    assert result.code == 0, result.err
    return out


def test_every_script_parses_with_sh_n(built: Path) -> None:
    names = {p.name for p in scripts(built)}
    assert {"env.sh", "start-all", "stop-all"} <= names
    for path in scripts(built):
        done = subprocess.run(["sh", "-n", str(path)], capture_output=True, text=True)
        assert done.returncode == 0, (path, done.stderr)


@pytest.mark.service
def test_shellcheck_finds_nothing(built: Path) -> None:
    found = shutil.which("shellcheck")
    if found is None:
        reason = "shellcheck is not on PATH (apt-get install shellcheck)"
        if os.environ.get("CI") == "true":
            pytest.fail(f"the shellcheck test cannot run in CI: {reason}")
        pytest.skip(reason)
    done = subprocess.run(
        [found, "-s", "sh", "-x", *(p.name for p in scripts(built))],
        cwd=built / "bin",
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr


@pytest.mark.parametrize("text", ["", "a b", "it's", "$(x)`y`", "'", "\n\\\"'", "'\\''"])
def test_quote_gives_the_string_back_through_sh(text: str) -> None:
    done = subprocess.run(
        ["sh", "-c", f"printf '%s' {quote(text)}"], capture_output=True, text=True
    )
    assert done.stdout == text


def test_quote_refuses_nul() -> None:
    with pytest.raises(ValueError):
        quote("a\0b")


def test_hostile_strings_reach_the_program_as_data(weblab, tmp_path: Path) -> None:
    pwned = tmp_path / "pwned-XYZ"
    evil = f"$(touch {pwned})`touch {pwned}`'; touch {pwned}; '\n# END USER application\n"
    c0 = weblab.containers[0]
    app = dataclasses.replace(
        weblab,
        containers=(
            dataclasses.replace(
                c0, host="h" + evil, id="id" + evil, documentation=evil, qualified_name="Q" + evil
            ),
            *weblab.containers[1:],
        ),
    )
    made = context(app, tmp_path, "shell")
    shell(made)
    out = tmp_path / "out"
    for f in made.files:
        (out / f.path).parent.mkdir(parents=True, exist_ok=True)
        (out / f.path).write_bytes(f.data)
    args = tmp_path / "args"
    fake = tmp_path / "fake-python"
    fake.write_text(f"#!/bin/sh\nprintf '%s\\0' \"$@\" >'{args}'\nexec sleep 30\n")
    fake.chmod(0o755)
    env = {**os.environ, "PYTHON": str(fake), "ACORDCS_RUN_DIR": str(tmp_path / "run")}
    env.pop(f"ACORDCS_{c0.name}_HOST", None)
    bin_ = out / "bin"
    try:
        done = subprocess.run(["sh", str(bin_ / f"{c0.name}-start")], env=env, capture_output=True)
        assert done.returncode == 0, done.stderr
        for verb in ("status", "stop"):
            subprocess.run(["sh", str(bin_ / f"{c0.name}-{verb}")], env=env, check=True)
    finally:
        subprocess.run(["sh", str(bin_ / "stop-all")], env=env, capture_output=True)
    given = args.read_bytes().split(b"\0")
    assert given[given.index(b"--host") + 1].decode() == "h" + evil
    assert not pwned.exists()


def free_ports(count: int) -> list[int]:
    sockets = [socket.socket() for _ in range(count)]
    try:
        for s in sockets:
            s.bind(("127.0.0.1", 0))
        return [s.getsockname()[1] for s in sockets]
    finally:
        for s in sockets:
            s.close()


def test_needs_is_what_assembly_requires(weblab, smartroom) -> None:
    from acordcs.runtime.api import VirtualClock
    from acordcs.runtime.assembly import assemble
    from acordcs.runtime.errors import RuntimeFailure

    assert needs(weblab, "UserSide") == ["WebLabSide"]
    assert needs(weblab, "WebLabSide") == ["UserSide"]
    for app in (weblab, smartroom):
        for c in app.containers:
            given = needs(app, c.name)
            uris = {n: f"PYRO:acordcs.container.{n}@127.0.0.1:9" for n in given}
            assemble(app, only=[c.name], clock=VirtualClock(0), remote=uris).close()
            for missing in given:
                fewer = {n: u for n, u in uris.items() if n != missing}
                with pytest.raises(RuntimeFailure):
                    assemble(app, only=[c.name], clock=VirtualClock(0), remote=fewer)


# User code for the two-process run, written where the build keeps it (the user classes): the
# Navigator (UserSide) grabs a frame and moves the robot (WebLabSide) every 0.2 s over the remote
# connector; the Control monitor turns each move into the SpeedLimiting policy's inputs, whose
# firing caps Locomotion.maxSpeed in the WebLab's process; Usage polls Access.countUsers.
USER_CODE = {
    "components/Navigator.py": """
from weblab_app.base.Navigator import NavigatorBase


class Navigator(NavigatorBase):
    def on_start(self):
        self.frames = 0
        self.clock.call_every(0.2, self.step)

    def step(self):
        try:
            frame = self.port("NavVisionPort").call("grab")
            self.port("NavLocomotionPort").call("move", 150.0, 4.0)
        except Exception as err:  # the WebLab's process may not serve yet
            print(f"Navigator: waiting ({type(err).__name__})", flush=True)
            return False
        self.frames += 1
        print(f"Navigator: frame {self.frames}: {type(frame).__name__} of {len(frame)}", flush=True)
        return True
""",
    "components/Vision.py": """
import os

from weblab_app.base.Vision import VisionBase


class Vision(VisionBase):
    def grab(self):
        return b"\\xff\\xd8" + os.getpid().to_bytes(4, "big") * 100
""",
    "components/Locomotion.py": """
from weblab_app.base.Locomotion import LocomotionBase


class Locomotion(LocomotionBase):
    def move(self, speed, turn):
        print(f"Locomotion: move {speed} under maxSpeed {self.get('maxSpeed'):.1f}", flush=True)
        self.publish_context(f"<telemetry><heading>{turn}</heading></telemetry>")
""",
    "components/Access.py": """
from weblab_app.base.Access import AccessBase


class Access(AccessBase):
    def countUsers(self):
        return 2
""",
    "monitors/Control.py": """
from weblab_app.base.Control import ControlBase


class Control(ControlBase):
    last = None

    def on_call(self, call):
        if call.operation != "move":
            return None
        speed, turn = call.args
        rate = 0.0 if self.last is None else 1.0 / max(call.time - self.last, 1e-3)
        self.last = call.time
        return {"cycleRate": min(rate, 3.0), "angle": abs(turn), "speed": speed}
""",
}


def test_the_weblab_scripts_start_check_and_stop_both_containers(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-t", "python,shell").code == 0
    for rel, code in USER_CODE.items():
        (out / "weblab_app" / rel).write_text(code, encoding="utf-8")
    run = tmp_path / "run"
    ports = free_ports(2)
    env = {
        **os.environ,
        "PYTHON": sys.executable,
        "PYTHONPATH": str(SRC),
        "ACORDCS_RUN_DIR": str(run),
        "ACORDCS_CLOCK": "real",
        "ACORDCS_STOP_TIMEOUT": "5",
    }
    env.pop("ACORDCS_TOKEN", None)  # env.sh makes one, shared through the run directory
    for name, port in zip(("UserSide", "WebLabSide"), ports, strict=True):
        env[f"ACORDCS_{name}_HOST"] = "127.0.0.1"
        env[f"ACORDCS_{name}_PORT"] = str(port)
    bin_ = out / "bin"

    def sh(script: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            ["sh", str(bin_ / script)], env=env, capture_output=True, text=True, timeout=60
        )

    try:
        started = sh("start-all")
        assert started.returncode == 0, started.stdout + started.stderr
        for name in ("UserSide", "WebLabSide"):
            status = sh(f"{name}-status")
            assert status.returncode == 0 and f"{name}: running (pid" in status.stdout
            assert (run / f"{name}.pid").is_file()
        again = sh("UserSide-start")
        assert again.returncode == 2 and "already running" in again.stderr
        # Each serves the endpoint the other was given with --remote, to callers presenting
        # the application's token only.
        from Pyro5.api import Proxy
        from Pyro5.errors import CommunicationError

        token = (run / "token").read_text()
        assert len(token) == 32 and (run / "token").stat().st_mode & 0o077 == 0

        deadline = time.monotonic() + 20
        for name, port in zip(("UserSide", "WebLabSide"), ports, strict=True):
            uri = f"PYRO:acordcs.container.{name}@127.0.0.1:{port}"
            while f"{name}: serving at {uri}" not in (run / f"{name}.log").read_text():
                assert time.monotonic() < deadline, (run / f"{name}.log").read_text()
                time.sleep(0.1)
            with Proxy(uri) as proxy:
                proxy._pyroHandshake = token
                proxy._pyroBind()
            with Proxy(uri) as stranger, pytest.raises(CommunicationError, match="token"):
                stranger._pyroBind()
        # The processes talk: frames from the WebLab reach the user's process as bytes, and
        # the moves reach the WebLab, where the speed policy (fed by the Control monitor that
        # intercepts them) has set maxSpeed away from the model's default of 200.
        user_log, lab_log = run / "UserSide.log", run / "WebLabSide.log"
        while "Navigator: frame 5: bytes of 402" not in user_log.read_text():
            assert time.monotonic() < deadline, user_log.read_text() + lab_log.read_text()
            time.sleep(0.1)
        limits = [
            float(line.rsplit(" ", 1)[1])
            for line in lab_log.read_text().splitlines()
            if line.startswith("Locomotion: move 150.0 under maxSpeed")
        ]
        assert limits and any(limit != 200.0 for limit in limits), lab_log.read_text()
    finally:
        stopped = sh("stop-all")
    assert stopped.returncode == 0, stopped.stderr
    assert "UserSide: stopped" in stopped.stdout and "WebLabSide: stopped" in stopped.stdout
    for name in ("UserSide", "WebLabSide"):
        # TERM stops the container as Ctrl-C does: its last line, no fault.
        log = (run / f"{name}.log").read_text()
        assert f"{name}: stopped at t=" in log and "faults: 0" in log, log
        status = sh(f"{name}-status")
        assert status.returncode == 3 and f"{name}: not running" in status.stdout
        assert not (run / f"{name}.pid").exists()
    again = sh("stop-all")
    assert again.returncode == 0 and "UserSide: not running" in again.stdout


def test_readme_excerpt_is_the_end_of_the_weblab_env_file(tmp_path: Path) -> None:
    from tests.codegen.test_readme_build_section import blocks

    assert build(WEBLAB, tmp_path, "-t", "shell").code == 0
    (excerpt,) = [b for b in blocks("sh") if b.startswith("# Container")]
    assert (tmp_path / "bin" / "env.sh").read_text(encoding="utf-8").endswith(excerpt)


def test_scripts_are_executable_and_env_file_is_not(built: Path) -> None:
    for path in scripts(built):
        assert os.access(path, os.X_OK) == (path.name != "env.sh"), path


def test_a_container_name_that_is_no_identifier_is_refused(weblab, tmp_path: Path) -> None:
    from acordcs.codegen.errors import BuildError

    c0 = weblab.containers[0]
    app = dataclasses.replace(
        weblab, containers=(dataclasses.replace(c0, name="U$(touch x)"), *weblab.containers[1:])
    )
    made = context(app, tmp_path, "shell")
    with pytest.raises(BuildError) as info:
        shell(made)
    assert [d.code for d in info.value.diagnostics] == ["G703"] and made.files == []
