"""A container's exit status tells how it ended (acordcs.runtime.launcher): 0 no fault, 3 faults
recorded (0 with ``--faults-ok``), 1 a failed ``--run``, 2 not started; ``--exit-file PATH``
records ``EXIT_CODE FAULTS`` in one line, mode 0600, replacing what was there (a symlink planted
there is replaced, its target untouched), also for a usage error."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest

from tests.support.generator import build, run_container

REMOTE = ("--remote", "WebLabSide=PYRO:acordcs.container.WebLabSide@127.0.0.1:9")
LAB_REMOTE = ("--remote", "UserSide=PYRO:acordcs.container.UserSide@127.0.0.1:9")


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    from tests.support.toolchain import WEBLAB

    out = tmp_path_factory.mktemp("status") / "out"
    result = build(WEBLAB, out, "-t", "python")
    assert result.code == 0, result.both
    return out


def ended(path: Path) -> str:
    assert stat.S_IMODE(path.lstat().st_mode) == 0o600 and path.is_file() and not path.is_symlink()
    return path.read_text(encoding="ascii")


def test_faults_exit_3_and_the_exit_file_counts_them(built: Path, tmp_path: Path) -> None:
    # A fresh build has no code for Access.countUsers, which the Usage monitor polls at 1 Hz.
    exit_file = tmp_path / "lab.exit"
    done = run_container(built, "weblab_app.WebLabSide", *LAB_REMOTE, "--duration", "5",
                         "--exit-file", str(exit_file))  # fmt: skip
    assert done.returncode == 3, done.stderr
    assert done.stdout.splitlines()[-1] == "WebLabSide: stopped at t=5.000 s, faults: 10"
    assert ended(exit_file) == "3 10\n"


def test_faults_ok_exits_0_and_still_counts_them(built: Path, tmp_path: Path) -> None:
    exit_file = tmp_path / "lab.exit"
    done = run_container(built, "weblab_app.WebLabSide", *LAB_REMOTE, "--duration", "5",
                         "--faults-ok", "--exit-file", str(exit_file))  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert ended(exit_file) == "0 10\n"


def test_no_fault_exits_0(built: Path, tmp_path: Path) -> None:
    exit_file = tmp_path / "user.exit"
    exit_file.write_text("stale\n", encoding="ascii")
    exit_file.chmod(0o644)
    done = run_container(built, "weblab_app.UserSide", *REMOTE, "--duration", "2",
                         "--exit-file", str(exit_file))  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["UserSide: stopped at t=2.000 s, faults: 0"]
    assert ended(exit_file) == "0 0\n"


def test_a_failed_run_exits_1(built: Path, tmp_path: Path) -> None:
    exit_file = tmp_path / "user.exit"
    done = run_container(built, "weblab_app.UserSide", *REMOTE, "--run", "Navigator.run",
                         "--exit-file", str(exit_file))  # fmt: skip
    assert done.returncode == 1, done.stderr
    assert ended(exit_file) == "1 1\n"


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (("--duration", "soon"), "argument --duration: invalid float value: 'soon'"),
        ((), "give the address of each one this container reaches with --remote NAME=URI"),
        ((*REMOTE, "--run", "Navigator.fly"), "component 'Navigator' has no operation 'fly'"),
    ],
    ids=["usage", "no-remote", "unknown-run"],
)
def test_not_started_exits_2(built: Path, tmp_path: Path, args: tuple[str, ...], says: str) -> None:
    exit_file = tmp_path / "user.exit"
    done = run_container(built, "weblab_app.UserSide", *args, "--exit-file", str(exit_file))
    assert done.returncode == 2, done.stdout + done.stderr
    assert says in done.stderr and "Traceback" not in done.stderr
    # the addresses of the others are asked for only when one is missing
    assert ("give the address of each one" in done.stderr) == (args == ()), done.stderr
    assert ended(exit_file) == "2 0\n"


def test_a_symlink_at_the_exit_file_is_replaced_not_followed(built: Path, tmp_path: Path) -> None:
    victim = tmp_path / "victim"
    victim.write_text("keep me\n", encoding="ascii")
    exit_file = tmp_path / "user.exit"
    exit_file.symlink_to(victim)
    done = run_container(built, "weblab_app.UserSide", *REMOTE, "--duration", "1",
                         "--exit-file", str(exit_file))  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert ended(exit_file) == "0 0\n"
    assert victim.read_text(encoding="ascii") == "keep me\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["user.exit", "victim"]  # no temporary


def test_an_exit_file_in_a_missing_directory_is_a_usage_error(built: Path, tmp_path: Path) -> None:
    done = run_container(built, "weblab_app.UserSide", *REMOTE,
                         "--exit-file", str(tmp_path / "no" / "user.exit"))  # fmt: skip
    assert done.returncode == 2
    assert "does not exist (create it first)" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "no").exists()


def test_the_help_documents_the_exit_status(built: Path) -> None:
    done = run_container(built, "weblab_app.UserSide", "--help")
    assert done.returncode == 0, done.stderr
    for line in (
        "exit status:",
        "0  stopped with no fault recorded (or with faults, given --faults-ok)",
        "1  a --run operation failed",
        "2  not started:",
        "3  stopped after recording faults (the last line says how many)",
    ):
        assert line in done.stdout
    for option in ("--faults-ok", "--strict", "--exit-file PATH"):
        assert option in done.stdout


def test_term_stops_a_serving_container_and_its_exit_file_says_so(
    built: Path, tmp_path: Path
) -> None:
    import os
    import signal
    import subprocess
    import sys

    from tests.support.toolchain import ROOT

    exit_file = tmp_path / "user.exit"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(built), str(ROOT / "src")]))
    command = [sys.executable, "-m", "weblab_app.UserSide", *REMOTE, "--clock", "real",
               "--serve", "0", "--host", "127.0.0.1", "--exit-file", str(exit_file)]  # fmt: skip
    process = subprocess.Popen(command, cwd=built, env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert process.stdout is not None
        first = process.stdout.readline()  # it serves
        assert first.startswith("UserSide: serving at PYRO:acordcs.container.UserSide@127.0.0.1:")
        # ready: its start-up said all it says (a TERM before the second line may come first)
        second = process.stdout.readline()
        assert second.startswith("UserSide: runs descriptor sha256 "), second
        process.send_signal(signal.SIGTERM)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 0, err
    assert out.startswith("UserSide: stopped at t=") and out.endswith(", faults: 0\n")
    assert ended(exit_file) == "0 0\n"
