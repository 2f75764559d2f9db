"""The generated scripts check their numeric settings before doing anything: a timeout, port or
port base that is not a whole number in range (or a number of seconds) stops the script with one
line naming the variable, its value and what to set it to, exit 2 (``-status``: 4, LSB's status
unknown); nothing is started or signalled. Before, ``ACORDCS_STOP_TIMEOUT=abc`` made stop print
"Illegal number" every second and never send KILL (issue 22, item 10)."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from tests.support.scripts import alive, built, environment, script, wait_until


@pytest.fixture(scope="module")
def bin_(tmp_path_factory) -> Path:
    return built(tmp_path_factory.mktemp("settings") / "out")


@pytest.fixture
def run(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    run.mkdir(mode=0o700)
    return run


def test_a_stop_timeout_that_is_no_number_is_refused_before_any_signal(bin_: Path, run: Path):
    # A container that ignores TERM: before, stop looped on "Illegal number" and never killed it.
    env = environment(run, FAKE_IGNORE_TERM="1")
    assert script(bin_, "UserSide-start", env).returncode == 0
    pid = int((run / "UserSide.pid").read_text())
    try:
        done = script(bin_, "UserSide-stop", {**env, "ACORDCS_STOP_TIMEOUT": "abc"}, timeout=20)
        assert done.returncode == 2, done.stdout + done.stderr
        assert done.stderr == (
            "UserSide-stop: ACORDCS_STOP_TIMEOUT is 'abc', not a whole number (decimal digits, "
            "no sign, no leading zero): set it to one from 0 to 86400\n"
        )
        assert alive(pid) and (run / "UserSide.pid").exists()
        killed = script(bin_, "UserSide-stop", {**env, "ACORDCS_STOP_TIMEOUT": "0"})
        assert killed.returncode == 0 and "UserSide: killed" in killed.stdout, killed.stdout
    finally:
        subprocess.run(["kill", "-KILL", str(pid)], capture_output=True)
    wait_until(lambda: not alive(pid), "the container gone")


CASES = [
    ("ACORDCS_STOP_TIMEOUT", "-1", "not a whole number"),
    ("ACORDCS_STOP_TIMEOUT", "010", "not a whole number"),
    ("ACORDCS_STOP_TIMEOUT", "99999999999999999999999", "out of range"),
    ("ACORDCS_START_TIMEOUT", "0", "out of range: set it to a whole number from 1 to 86400"),
    ("ACORDCS_START_TIMEOUT", "2.5", "not a whole number"),
    ("ACORDCS_PORT_BASE", "abc", "not a whole number"),
    ("ACORDCS_PORT_BASE", "65536", "out of range: set it to a whole number from 0 to 65535"),
    ("ACORDCS_UserSide_PORT", "http", "not a whole number"),
    ("ACORDCS_UserSide_PORT", "0", "out of range: set it to a whole number from 1 to 65535"),
    ("ACORDCS_WebLabSide_PORT", "70000", "out of range"),
    ("ACORDCS_UserSide_PORT", " 80", "not a whole number"),
    ("ACORDCS_TIMEOUT", "abc", "not a number of seconds"),
    ("ACORDCS_TIMEOUT", "0", "set it to a number of seconds above 0"),
    ("ACORDCS_TIMEOUT", "1.2.3", "not a number of seconds"),
    ("ACORDCS_DURATION", "-5", "not a number of seconds"),
    ("ACORDCS_CLOCK", "fast", "set it to real or virtual"),
]


@pytest.mark.parametrize(("name", "value", "said"), CASES, ids=[f"{n}={v}" for n, v, _ in CASES])
def test_a_bad_setting_stops_every_script_naming_it(bin_, run, name, value, said):
    env = environment(run, **{name: value})
    try:
        started = script(bin_, "UserSide-start", env)
    finally:  # were it started anyway
        script(bin_, "UserSide-stop", environment(run))
    assert started.returncode == 2, started.stdout + started.stderr
    assert started.stderr.startswith(f"UserSide-start: {name} is ") and said in started.stderr
    assert started.stderr.count("\n") == 1, started.stderr
    assert not (run / "UserSide.log").exists() and not (run / "UserSide.pid").exists()
    status = script(bin_, "UserSide-status", env)
    assert status.returncode == 4 and f"UserSide-status: {name} is " in status.stderr


def test_a_port_base_that_pushes_a_port_beyond_65535_names_that_port(bin_, run):
    done = script(bin_, "UserSide-start", environment(run, ACORDCS_PORT_BASE="65535"))
    assert done.returncode == 2
    assert "ACORDCS_UserSide_PORT is 65536, out of range" in done.stderr, done.stderr


def test_good_settings_reach_the_module(bin_, run, tmp_path: Path):
    args = tmp_path / "args"
    env = environment(
        run,
        FAKE_ARGS=str(args),
        ACORDCS_PORT_BASE="40000",
        ACORDCS_TIMEOUT="2.5",
        ACORDCS_DURATION="60",
        ACORDCS_CLOCK="virtual",
        ACORDCS_WebLabSide_PORT="40123",
        ACORDCS_UserSide_RUN="Navigator.run *",
    )
    try:
        started = script(bin_, "UserSide-start", env)
        assert started.returncode == 0, started.stdout + started.stderr
    finally:
        script(bin_, "UserSide-stop", env)
    given = args.read_text().split("\0")
    assert given[:2] == ["--exit-file", f"{run}/UserSide.exit"]
    pairs = dict(zip(given[2::2], given[3::2], strict=False))
    assert pairs["--serve"] == "40001" and pairs["--timeout"] == "2.5"
    assert pairs["--clock"] == "virtual" and pairs["--duration"] == "60"
    assert "WebLabSide=PYRO:acordcs.container.WebLabSide@weblab.example.org:40123" in given
    # ACORDCS_UserSide_RUN's words are not globbed: '*' stays '*'.
    assert given[-4:] == ["--run", "Navigator.run", "--run", "*"]


def test_the_docs_example_is_what_stop_says(bin_: Path, run: Path):
    from tests.support.toolchain import ROOT

    page = (ROOT / "docs" / "build.md").read_text(encoding="utf-8")
    command = "$ ACORDCS_STOP_TIMEOUT=abc bin/UserSide-stop\n"
    shown = page.split(command, 1)[1].split("\n", 1)[0]
    done = script(bin_, "UserSide-stop", environment(run, ACORDCS_STOP_TIMEOUT="abc"))
    assert done.stderr == shown + "\n"
