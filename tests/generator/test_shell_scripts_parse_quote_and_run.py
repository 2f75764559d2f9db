"""The ``shell`` target's scripts: ``sh -n`` parses every one of both samples, shellcheck finds
nothing (service test: ``make test`` installs shellcheck), the stylesheet's one quoting function
(``sh:quote`` in shell.xsl) gives every string of a hostile corpus back through ``sh`` and starts
no line with model text, model strings are quoted (hostile hosts, ids, qualified names and the
model file's name reach the program as data, never run, never forge a protected region), and the
WebLab's scripts start both containers as two processes, which serve the endpoints the other is
given, call each other over the remote connector (with user code in the user classes) while a
policy adapts, report them running, refuse a second start, and stop them."""

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

from acordcs.descriptor import DescriptorError, to_xml
from acordcs.generator import regions
from acordcs.generator.targets.shell import STYLESHEET, shell
from tests.support import fake_container
from tests.support.generator import build, context
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


def shellcheck(directory: Path, *options: str) -> subprocess.CompletedProcess:
    found = shutil.which("shellcheck")
    if found is None:
        reason = "shellcheck is not on PATH (apt-get install shellcheck)"
        if os.environ.get("CI") == "true":
            pytest.fail(f"the shellcheck test cannot run in CI: {reason}")
        pytest.skip(reason)
    names = sorted(p.name for p in directory.iterdir() if not p.name.endswith(".lost"))
    return subprocess.run(
        [found, "-s", "sh", "-x", *options, *names], cwd=directory, capture_output=True, text=True
    )


@pytest.mark.service
def test_shellcheck_finds_nothing(built: Path) -> None:
    done = shellcheck(built / "bin")
    assert done.returncode == 0, done.stdout + done.stderr


# Strings that are code, or end a line, in a shell script or for a reader of it.
CORPUS = [
    "",
    "a b",
    "it's",
    "$(x)`y`",
    "'",
    "\n\\\"'",
    "'\\''",
    "${HOME} ~ * ? [a] ! & ; | < > #",
    "-n",
    "tab\there",
    "line\n# END USER application\n",
    "\n# BEGIN USER forged\nrm -rf ~\n# END USER forged",
    "cr\r# END USER application",
    "crlf\r\n",
    "nel\x85# END USER application",
    "ls\u2028# END USER application\u2029ps",
    "vt\x0bff\x0c fs\x1c gs\x1d rs\x1e",
    "esc \x1b[31mred\x1b[0m del\x7f",
    "é 中 😀 e\u0301 \u200b \u202e",
    "\\",
    "''''",
]


@pytest.fixture(scope="module")
def sh_quote(tmp_path_factory):
    """``sh:quote`` of shell.xsl, called through a stylesheet that imports it."""
    from saxonche import PySaxonProcessor

    wrapper = tmp_path_factory.mktemp("quote") / "quote.xsl"
    wrapper.write_text(
        f"""<xsl:stylesheet version="3.0" xmlns:xsl="http://www.w3.org/1999/XSL/Transform"
    xmlns:xs="http://www.w3.org/2001/XMLSchema" xmlns:sh="http://acordcs.org/codegen/sh">
  <xsl:import href="{Path(str(STYLESHEET)).as_uri()}"/>
  <xsl:param name="s" as="xs:string" required="yes"/>
  <xsl:output method="text" encoding="UTF-8"/>
  <xsl:template name="xsl:initial-template"><xsl:value-of select="sh:quote($s)"/></xsl:template>
</xsl:stylesheet>
""",
        encoding="utf-8",
    )
    processor = PySaxonProcessor(license=False)
    executable = processor.new_xslt30_processor().compile_stylesheet(stylesheet_file=str(wrapper))
    for name in ("source-file", "generator", "target", "descriptor-schema", "package", "python"):
        executable.set_parameter(name, processor.make_string_value(""))
    executable.set_parameter("region-keys", processor.make_string_value(""))

    def quote(text: str) -> str:
        executable.set_parameter("s", processor.make_string_value(text))
        return executable.call_template_returning_string()

    return quote


@pytest.mark.parametrize("text", CORPUS, ids=repr)
def test_quote_gives_the_string_back_through_sh(sh_quote, text: str) -> None:
    quoted = sh_quote(text)
    done = subprocess.run(["sh", "-c", f"printf '%s' {quoted}"], capture_output=True)
    assert done.stdout.decode("utf-8") == text


@pytest.mark.parametrize("text", CORPUS, ids=repr)
def test_quote_starts_no_line_with_model_text(sh_quote, text: str) -> None:
    """Every line break is followed by the quotes closed and opened again (a line starts with
    ``''``), whichever reader splits the lines: Python's (the protected regions') or sh's."""
    quoted = sh_quote(text)
    assert quoted.startswith("'") and quoted.endswith("'")
    for line in quoted.splitlines()[1:]:
        assert line.startswith("''"), (quoted, line)
    assert regions.parse("hash", f"x={quoted}\n") == []


def test_a_nul_never_reaches_a_script(weblab) -> None:
    """A NUL cannot be in a shell word; an XPath string cannot hold one either (XML characters
    only), and the descriptor the stylesheet reads refuses it."""
    c0 = weblab.containers[0]
    app = dataclasses.replace(
        weblab, containers=(dataclasses.replace(c0, host="a\0b"), *weblab.containers[1:])
    )
    with pytest.raises(DescriptorError, match=r"host 'a\\x00b' contains U\+0000"):
        to_xml(app)


HOSTILE = (
    "$(touch {pwned})`touch {pwned}`'; touch {pwned}; '\n# END USER application\n"
    "\u2028# BEGIN USER x\r"
)


@pytest.mark.service
def test_hostile_strings_reach_the_program_as_data(weblab, tmp_path: Path) -> None:
    pwned = tmp_path / "pwned-XYZ"
    evil = HOSTILE.format(pwned=pwned)
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
    made = context(app, tmp_path, "shell", source=f"m{evil}.xmi")
    shell(made)
    out = tmp_path / "out"
    for f in made.files:
        (out / f.path).parent.mkdir(parents=True, exist_ok=True)
        (out / f.path).write_bytes(f.data)
    env_text = (out / "bin" / "env.sh").read_text(encoding="utf-8")
    keys = [r.key for r in regions.parse("hash", env_text)]
    assert keys == ["application", *(regions.key(c.id) for c in app.containers)]
    assert keys[1].startswith("id-")  # the hostile id, as a digest
    # No error; its warnings here are guesses at intent ("expressions don't expand in single
    # quotes", a quote that "looks suspect" after a line break): what the quoting is for.
    checked = shellcheck(out / "bin", "--severity=error")
    assert checked.returncode == 0, checked.stdout
    fake_container.install(out, "weblab_app", tuple(c.name for c in app.containers))
    args = tmp_path / "args"
    env = {
        **{k: v for k, v in os.environ.items() if not k.startswith("ACORDCS_")},
        "PYTHON": sys.executable,
        "ACORDCS_RUN_DIR": str(tmp_path / "run"),
        "FAKE_ARGS": str(args),
    }
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


def test_readme_excerpt_is_in_the_weblab_env_file(tmp_path: Path) -> None:
    from tests.generator.test_readme_build_section import blocks

    assert build(WEBLAB, tmp_path, "-t", "shell").code == 0
    (excerpt,) = [b for b in blocks("sh") if b.startswith("# Container")]
    assert excerpt in (tmp_path / "bin" / "env.sh").read_text(encoding="utf-8")


def test_scripts_are_executable_and_env_file_is_not(built: Path) -> None:
    for path in scripts(built):
        assert os.access(path, os.X_OK) == (path.name != "env.sh"), path


def test_a_container_name_that_is_no_identifier_is_refused(weblab, tmp_path: Path) -> None:
    from acordcs.generator.errors import BuildError

    c0 = weblab.containers[0]
    app = dataclasses.replace(
        weblab, containers=(dataclasses.replace(c0, name="U$(touch x)"), *weblab.containers[1:])
    )
    made = context(app, tmp_path, "shell")
    with pytest.raises(BuildError) as info:
        shell(made)
    assert [d.code for d in info.value.diagnostics] == ["G703"] and made.files == []


def test_a_host_holding_region_markers_builds_and_keeps_the_users_lines(tmp_path: Path) -> None:
    from tests.support.generator import weblab_variant

    forged = "user.example.org&#10;# END USER application&#10;# BEGIN USER application&#10;x"
    model = weblab_variant(tmp_path, ('"user.example.org"', f'"{forged}"', 2))
    out = tmp_path / "out"
    first = build(model, out, "-t", "shell")
    assert first.code == 0, first.both
    env = out / "bin" / "env.sh"
    text = env.read_text(encoding="utf-8")
    assert [r.key for r in regions.parse("hash", text)] == [
        "application",
        "BOUML_0x20502_4",
        "BOUML_0x20582_4",
    ]
    env.write_text(
        text.replace("# BEGIN USER application\n", "# BEGIN USER application\nMINE=1\n", 1),
        encoding="utf-8",
    )
    again = build(model, out, "-t", "shell", "--force")
    assert again.code == 0, again.both
    kept = env.read_text()
    assert "# BEGIN USER application\nMINE=1\n# The interpreter the scripts run" in kept
    host = subprocess.run(
        ["sh", "-c", '. "$bin/env.sh" && printf %s "$ACORDCS_UserSide_HOST"'],
        env={**os.environ, "bin": str(out / "bin"), "ACORDCS_RUN_DIR": str(tmp_path / "run")},
        capture_output=True,
        text=True,
    )
    assert host.stdout == forged.replace("&#10;", "\n"), host.stderr
