"""A generated ``<C>-stop`` signals only a process that runs container C from this run directory
(its command line has ``-m <package>.<C> --exit-file <run dir>/<C>.exit``): a pid file naming an
unrelated process of the same user, a process group (``-PGID``), every process (``-1``), the stop's
own group (``0``), text, nothing, a number beyond every pid, another run directory's container, or
a file that is no regular file is reported and removed, and nothing is signalled (each case with a
real process that must survive). A real container is stopped by TERM, or by KILL when it ignores
TERM (issue 22, items 2 and 10)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.scripts import (
    PACKAGE,
    alive,
    built,
    environment,
    pid_namespace,
    process,
    script,
    sleeper,
    wait_until,
)


@pytest.fixture(scope="module")
def bin_(tmp_path_factory) -> Path:
    return built(tmp_path_factory.mktemp("stop") / "out")


@pytest.fixture
def run(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    run.mkdir(mode=0o700)
    return run


def stop(bin_: Path, run: Path, **settings: str) -> subprocess.CompletedProcess:
    return script(bin_, "UserSide-stop", environment(run, **settings))


def assert_refused_and_removed(done: subprocess.CompletedProcess, run: Path, why: str) -> None:
    assert done.returncode == 0, done.stdout + done.stderr
    assert "UserSide: not running" in done.stdout
    assert f"UserSide: pid file {run}/UserSide.pid not used: {why}" in done.stderr, done.stderr
    assert "not signalled, removed" in done.stderr
    assert not (run / "UserSide.pid").exists() and not (run / "UserSide.pid").is_symlink()


def test_a_pid_file_naming_an_unrelated_process_does_not_signal_it(bin_: Path, run: Path):
    with sleeper() as victim:
        (run / "UserSide.pid").write_text(f"{victim.pid}\n")
        done = stop(bin_, run)
        assert alive(victim.pid)
    assert_refused_and_removed(done, run, f"process {victim.pid} does not run UserSide")


def test_a_negative_pid_does_not_signal_a_process_group(bin_: Path, run: Path):
    with sleeper(new_session=True) as victim:  # the leader of its own process group
        (run / "UserSide.pid").write_text(f"-{victim.pid}\n")
        done = stop(bin_, run)
        assert alive(victim.pid)
    assert_refused_and_removed(done, run, "it does not hold a process id")


def test_pid_zero_does_not_signal_the_stop_scripts_own_group(bin_: Path, run: Path, tmp_path):
    # A sleep in the stop script's own process group: kill 0 would reach both.
    (run / "UserSide.pid").write_text("0\n")
    marker = tmp_path / "sleeper"
    command = f'sleep 300 >/dev/null 2>&1 & echo $! >"{marker}"; sh "$0"; echo "stop exit $?"'
    done = subprocess.run(
        ["sh", "-c", command, str(bin_ / "UserSide-stop")],
        env=environment(run),
        capture_output=True,
        text=True,
        timeout=60,
        start_new_session=True,
    )
    pid = int(marker.read_text())
    try:
        assert alive(pid), done.stdout + done.stderr
        assert "stop exit 0" in done.stdout
    finally:
        subprocess.run(["kill", "-KILL", str(pid)], capture_output=True)
    assert "UserSide: pid file" in done.stderr and "does not hold a process id" in done.stderr


def test_minus_one_does_not_signal_every_process_in_a_pid_namespace(bin_: Path, run: Path):
    prefix = pid_namespace()
    (run / "UserSide.pid").write_text("-1\n")
    inside = (
        'sleep 300 >/dev/null 2>&1 & victim=$!; sh "$0"; echo "stop exit $?"; '
        'if kill -0 "$victim" 2>/dev/null; then echo victim alive; else echo victim dead; fi; '
        'kill -KILL "$victim" 2>/dev/null; wait'
    )
    done = subprocess.run(
        [*prefix, "sh", "-c", inside, str(bin_ / "UserSide-stop")],
        env=environment(run),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert "victim alive" in done.stdout and "stop exit 0" in done.stdout, done.stdout + done.stderr
    assert "does not hold a process id" in done.stderr


@pytest.mark.parametrize(
    "text",
    ["", "\n", "abc\n", "12 34\n", "+5\n", "0x10\n", "007\n", "99999999999999999999\n", "1e3\n"],
    ids=repr,
)
def test_a_pid_file_that_holds_no_process_id_is_removed(bin_: Path, run: Path, text: str):
    (run / "UserSide.pid").write_text(text)
    assert_refused_and_removed(stop(bin_, run), run, "it does not hold a process id")


def test_a_pid_file_that_is_no_regular_file_is_not_read(bin_: Path, run: Path, tmp_path: Path):
    import os

    with sleeper() as victim:
        target = tmp_path / "elsewhere.pid"
        target.write_text(f"{victim.pid}\n")
        (run / "UserSide.pid").symlink_to(target)
        assert_refused_and_removed(stop(bin_, run), run, "it is not a regular file")
        os.mkfifo(run / "UserSide.pid")  # reading a FIFO would block the script
        assert_refused_and_removed(stop(bin_, run), run, "it is not a regular file")
        assert alive(victim.pid) and target.exists()


def test_a_pid_of_a_process_that_ended_is_removed(bin_: Path, run: Path):
    with sleeper() as gone:
        pid = gone.pid
    assert not alive(pid)
    (run / "UserSide.pid").write_text(f"{pid}\n")
    assert_refused_and_removed(stop(bin_, run), run, f"no process {pid} runs")


def test_the_same_container_of_another_run_directory_is_not_signalled(
    bin_: Path, run: Path, tmp_path: Path
):
    other = tmp_path / "other-run" / "UserSide.exit"
    argv = (sys.executable, "-c", "import time; time.sleep(300)")
    with process(*argv, "-m", f"{PACKAGE}.UserSide", "--exit-file", str(other)) as twin:
        (run / "UserSide.pid").write_text(f"{twin.pid}\n")
        done = stop(bin_, run)
        assert alive(twin.pid)
    assert_refused_and_removed(done, run, f"process {twin.pid} does not run UserSide")


def test_a_process_that_runs_the_container_here_is_stopped(bin_: Path, run: Path):
    mine = run / "UserSide.exit"
    argv = (sys.executable, "-c", "import time; time.sleep(300)")
    with process(*argv, "-m", f"{PACKAGE}.UserSide", "--exit-file", str(mine)) as ours:
        (run / "UserSide.pid").write_text(f"{ours.pid}\n")
        done = stop(bin_, run)
        assert done.returncode == 0 and f"UserSide: stopped (pid {ours.pid})" in done.stdout
        assert ours.wait(timeout=10) == -15  # TERM
    assert not (run / "UserSide.pid").exists()


def test_a_container_ignoring_term_is_killed_after_the_stop_timeout(bin_: Path, run: Path):
    env = environment(run, FAKE_IGNORE_TERM="1", ACORDCS_STOP_TIMEOUT="1")
    started = script(bin_, "UserSide-start", env)
    assert started.returncode == 0, started.stdout + started.stderr
    pid = int((run / "UserSide.pid").read_text())
    done = script(bin_, "UserSide-stop", env, timeout=30)
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"UserSide: killed (pid {pid}): it did not stop within 1 s of TERM" in done.stdout
    assert f"UserSide: stopped (pid {pid})" in done.stdout
    wait_until(lambda: not alive(pid), f"process {pid} gone")
    assert (run / "UserSide.exit").read_text() == "killed\n"
    status = script(bin_, "UserSide-status", env)
    assert status.returncode == 1 and "killed by UserSide-stop" in status.stdout, status.stdout
