"""``bin/start-all`` reports a container that ends during its start-up as failed (exit 1, with the
end of its log), never as started. A container served on a real clock says it serves once its
start-up is over: its ``--run`` calls typed and checked (a call that does not fit is exit 2 before
anything starts), and their first moments passed (one that fails at once, as an operation
without code does, stops it before that line). One that said it serves and ended at once
(its exit file says how) is reported with its exit code, unless it ended cleanly. A ``--run``
that returns at once is logged after the line saying it serves. Before, ``start-all`` printed
"started", exited 0, and the container died 0.09 s later."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.support import scripts
from tests.support.greenhouse import built, environment, free_port, script


@pytest.fixture(scope="module")
def stub(tmp_path_factory) -> Path:
    """The greenhouse built with the sensor's stub: readTemperature() has no code."""
    return built(tmp_path_factory.mktemp("stub"), "python", "shell", code=None)[1]


@pytest.fixture(scope="module")
def coded(tmp_path_factory) -> Path:
    return built(tmp_path_factory.mktemp("coded"), "python", "shell")[1]


def start_all(app: Path, tmp_path: Path, **more: str):
    run = tmp_path / "run"
    run.mkdir(mode=0o700)
    env = environment(run, free_port(), **more)
    started = script(app, "start-all", env)
    status = script(app, "House-status", env)
    stopped = script(app, "stop-all", env)
    return started, status, stopped, run


def test_a_run_that_fails_at_once_fails_the_start(stub: Path, tmp_path: Path) -> None:
    started, status, _, run = start_all(stub, tmp_path, ACORDCS_House_RUN="Sensor.readTemperature")
    assert started.returncode == 1, started.stdout + started.stderr
    assert "House: started" not in started.stdout
    assert started.stderr.startswith(f"House: stopped before serving; the end of {run}/House.log:")
    assert "--run Sensor.readTemperature() failed at t=" in started.stderr
    assert "implement readTemperature() in components/Sensor.py" in started.stderr
    assert status.returncode == 1 and "it stopped with exit code 1" in status.stdout
    assert not (run / "House.pid").exists()
    assert "serving at" not in (run / "House.log").read_text()


def test_a_call_that_does_not_fit_fails_the_start_before_anything_runs(
    coded: Path, tmp_path: Path
) -> None:
    started, status, _, _ = start_all(
        coded, tmp_path, ACORDCS_House_RUN="Sensor.readTemperature(5)"
    )
    assert started.returncode == 1, started.stdout + started.stderr
    assert (
        "--run Sensor.readTemperature(5): Sensor.readTemperature() takes no argument, 1 given: "
        "give one value per parameter, in order" in started.stderr
    )
    assert status.returncode == 1 and "it stopped with exit code 2" in status.stdout


def test_a_run_that_returns_at_once_is_logged_after_serving(coded: Path, tmp_path: Path) -> None:
    started, status, stopped, run = start_all(
        coded, tmp_path, ACORDCS_House_RUN="Sensor.readTemperature"
    )
    assert started.returncode == 0, started.stdout + started.stderr
    assert started.stdout.startswith("House: started (pid ")
    assert status.returncode == 0 and stopped.returncode == 0
    lines = (run / "House.log").read_text().splitlines()
    assert lines[0].startswith("House: serving at PYRO:acordcs.container.House@127.0.0.1:")
    assert lines[1].startswith("House: runs descriptor sha256 ")
    assert lines[2].startswith("House: --run Sensor.readTemperature() returned 1.0 at t=0.")


@pytest.mark.parametrize(
    ("code", "exit", "says"),
    [
        ("1", 1, "UserSide: stopped during its start-up (exit 1, faults 0); the end of "),
        ("3", 1, "UserSide: stopped during its start-up (exit 3, faults 0); the end of "),
        ("0", 0, "UserSide: started and stopped at once, cleanly (exit 0, no fault; log "),
    ],
)
def test_a_container_that_ends_as_it_says_it_serves_is_reported_by_its_exit(
    tmp_path: Path, code: str, exit: int, says: str
) -> None:
    bin_ = scripts.built(tmp_path / "out")
    run = tmp_path / "run"
    run.mkdir(mode=0o700)
    env = scripts.environment(run, FAKE_EXIT_AFTER_SERVING=code, ACORDCS_START_TIMEOUT="60")
    started = scripts.script(bin_, "UserSide-start", env)
    assert started.returncode == exit, started.stdout + started.stderr
    assert says in (started.stderr if exit else started.stdout)
    if exit:
        assert "UserSide: fails at once (FAKE_EXIT_AFTER_SERVING)" in started.stderr
        assert "UserSide: started" not in started.stdout
    assert not (run / "UserSide.pid").exists()
