"""``<C>-status`` says whether container C runs and, when it does not, how it ended, from the line
``EXIT_CODE FAULTS`` its module writes to ``--exit-file`` at exit (``killed`` when ``<C>-stop`` had
to KILL it). Exit codes (LSB): 0 running; 3 not running, never started or stopped cleanly (exit 0,
no fault); 1 not running after a failure (another exit code, faults, killed, or gone without an
exit file while its pid file remains); 4 unknown (an exit file that does not read as one). The
exit files here are written by hand, as the runtime's launcher writes them (issue 21, item 2)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.support.scripts import built, environment, script, sleeper


@pytest.fixture(scope="module")
def bin_(tmp_path_factory) -> Path:
    return built(tmp_path_factory.mktemp("status") / "out")


@pytest.fixture
def run(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    run.mkdir(mode=0o700)
    return run


def status(bin_: Path, run: Path):
    return script(bin_, "UserSide-status", environment(run))


ENDINGS = [
    ("0 0\n", 3, "UserSide: not running (it stopped cleanly: exit 0, no fault)"),
    ("0 3\n", 1, "UserSide: not running: it stopped with exit code 0 and 3 faults; see "),
    ("1 0\n", 1, "UserSide: not running: it stopped with exit code 1 and 0 faults; see "),
    ("3 12", 1, "UserSide: not running: it stopped with exit code 3 and 12 faults; see "),
    ("killed\n", 1, "UserSide: not running: killed by UserSide-stop, TERM had not stopped it"),
    ("", 4, "does not hold EXIT_CODE FAULTS: how it ended is unknown"),
    ("0\n", 4, "does not hold EXIT_CODE FAULTS"),
    ("0 0 0\n", 4, "does not hold EXIT_CODE FAULTS"),
    ("zero none\n", 4, "does not hold EXIT_CODE FAULTS"),
    ("-1 0\n", 4, "does not hold EXIT_CODE FAULTS"),
    ("1x 0\n", 4, "does not hold EXIT_CODE FAULTS"),
]


@pytest.mark.parametrize(("line", "code", "said"), ENDINGS, ids=[repr(e[0]) for e in ENDINGS])
def test_a_container_that_is_not_running_reports_how_it_ended(bin_, run, line, code, said):
    (run / "UserSide.exit").write_text(line)
    done = status(bin_, run)
    assert done.returncode == code, done.stdout + done.stderr
    assert said in done.stdout, done.stdout


def test_never_started_is_not_running(bin_: Path, run: Path):
    done = status(bin_, run)
    assert (done.returncode, done.stdout) == (3, "UserSide: not running\n")


def test_gone_without_an_exit_file_while_its_pid_file_remains_is_a_failure(bin_, run):
    with sleeper() as gone:
        pid = gone.pid
    (run / "UserSide.pid").write_text(f"{pid}\n")
    done = status(bin_, run)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "UserSide: not running: it ended without saying how" in done.stdout
    assert f"no process {pid} runs" in done.stderr
    assert (run / "UserSide.pid").exists()  # status reports; it does not clean up


def test_an_exit_file_that_is_no_regular_file_is_unknown(bin_: Path, run: Path):
    (run / "UserSide.exit").mkdir()
    assert status(bin_, run).returncode == 4


def test_a_running_container_is_running_whatever_an_old_exit_file_says(bin_, run):
    env = environment(run)
    (run / "UserSide.exit").write_text("1 5\n")
    started = script(bin_, "UserSide-start", env)
    try:
        assert started.returncode == 0, started.stdout + started.stderr
        assert not (run / "UserSide.exit").exists()  # the start removed the last run's
        done = status(bin_, run)
        pid = int((run / "UserSide.pid").read_text())
        assert (done.returncode, done.stdout) == (0, f"UserSide: running (pid {pid})\n")
    finally:
        stopped = script(bin_, "UserSide-stop", env)
    assert stopped.returncode == 0
    after = status(bin_, run)
    assert after.returncode == 3 and "stopped cleanly" in after.stdout, after.stdout


def test_a_container_that_failed_to_start_says_so(bin_: Path, run: Path):
    env = environment(run, FAKE_FAIL="2")
    started = script(bin_, "UserSide-start", env)
    assert started.returncode == 1, started.stdout + started.stderr
    assert "UserSide: stopped before serving; the end of" in started.stderr
    assert "UserSide: cannot start (FAKE_FAIL)" in started.stderr
    done = status(bin_, run)
    assert done.returncode == 1 and "exit code 2 and 0 faults" in done.stdout, done.stdout
