"""``<C>-start`` returns once the container serves: it waits for the line ``<C>: serving at`` in
what the container logged since this start (an earlier run's line does not count), at most
``ACORDCS_START_TIMEOUT`` seconds; a container that stops first is reported with the end of its
log (exit 1) as soon as it stops; one that does not serve in time is reported and left running
(exit 1). Before, the script slept one second and declared it started."""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from tests.support.scripts import alive, built, environment, script


@pytest.fixture(scope="module")
def bin_(tmp_path_factory) -> Path:
    return built(tmp_path_factory.mktemp("start") / "out")


@pytest.fixture
def run(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    run.mkdir(mode=0o700)
    return run


def test_start_returns_once_the_container_serves(bin_: Path, run: Path):
    env = environment(run, FAKE_READY_AFTER="1.5")
    (run / "UserSide.log").write_text("UserSide: serving at PYRO:an-earlier-run\n")
    try:
        started = script(bin_, "UserSide-start", env)
        log = (run / "UserSide.log").read_text()
    finally:
        script(bin_, "UserSide-stop", env)
    assert started.returncode == 0, started.stdout + started.stderr
    assert log.count("UserSide: serving at ") == 2, log  # this run's line was there on return


def test_a_container_that_stops_before_serving_is_reported_at_once(bin_: Path, run: Path):
    env = environment(run, FAKE_FAIL="3", ACORDCS_START_TIMEOUT="60")
    began = time.monotonic()
    started = script(bin_, "UserSide-start", env)
    assert time.monotonic() - began < 30  # not the 60 s timeout
    assert started.returncode == 1
    assert started.stderr.startswith(f"UserSide: stopped before serving; the end of {run}/")
    assert "UserSide: cannot start (FAKE_FAIL)" in started.stderr
    assert not (run / "UserSide.pid").exists()


def test_a_container_that_does_not_serve_in_time_is_reported_and_left_running(bin_, run):
    env = environment(run, FAKE_READY_AFTER="never", ACORDCS_START_TIMEOUT="1")
    started = script(bin_, "UserSide-start", env)
    pid = int((run / "UserSide.pid").read_text())
    try:
        assert started.returncode == 1, started.stdout + started.stderr
        assert (
            f"UserSide: not serving after 1 s (ACORDCS_START_TIMEOUT); it still runs (pid {pid})"
            in started.stderr
        )
        assert alive(pid)
    finally:
        stopped = script(bin_, "UserSide-stop", env)
    assert stopped.returncode == 0 and f"UserSide: stopped (pid {pid})" in stopped.stdout
