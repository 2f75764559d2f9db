"""The generated scripts keep their pid files, logs and token in a run directory of the user's
alone: by default per user and per application (``$XDG_RUNTIME_DIR``, else ``/tmp``,
``/acordcs-<uid>/<package>``), made mode 0700, never the caller's working directory; a directory
owned by someone else, writable by others, or a symbolic link is refused with what to do. A token
file is used only when it is the user's, mode 0600: a planted one is refused, never becomes the
application's token (issue 22, items 2 and 5)."""

from __future__ import annotations

import os
import stat
import subprocess
from pathlib import Path

import pytest

from tests.support.scripts import PACKAGE, built, environment, script

NOBODY = 65534


@pytest.fixture(scope="module")
def bin_(tmp_path_factory) -> Path:
    return built(tmp_path_factory.mktemp("private") / "out")


def start_and_stop(bin_: Path, env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    started = subprocess.run(
        ["sh", str(bin_ / "UserSide-start")], env=env, cwd=cwd, capture_output=True, text=True
    )
    subprocess.run(["sh", str(bin_ / "UserSide-stop")], env=env, cwd=cwd, capture_output=True)
    return started


def mode(path: Path) -> int:
    return stat.S_IMODE(path.lstat().st_mode)


def test_the_default_run_directory_is_per_user_and_per_application(bin_: Path, tmp_path: Path):
    xdg = tmp_path / "xdg"
    xdg.mkdir(mode=0o700)
    cwd = tmp_path / "elsewhere"
    cwd.mkdir()
    started = start_and_stop(bin_, environment(None, XDG_RUNTIME_DIR=str(xdg)), cwd)
    assert started.returncode == 0, started.stdout + started.stderr
    mine = xdg / f"acordcs-{os.getuid()}"
    run = mine / PACKAGE
    assert (
        "UserSide: started (pid " in started.stdout and f"log {run}/UserSide.log" in started.stdout
    )
    assert mode(mine) == 0o700 and mode(run) == 0o700
    assert mode(run / "token") == 0o600 and len((run / "token").read_text()) == 32
    assert not (cwd / "run").exists()


def test_without_xdg_runtime_dir_it_is_under_tmpdir(bin_: Path, tmp_path: Path):
    done = script(bin_, "UserSide-status", environment(None, TMPDIR=str(tmp_path)))
    assert done.returncode == 3, done.stdout + done.stderr
    run = tmp_path / f"acordcs-{os.getuid()}" / PACKAGE
    assert mode(run.parent) == 0o700 and mode(run) == 0o700 and (run / "token").is_file()


def refused(bin_: Path, run: Path, **settings: str) -> subprocess.CompletedProcess:
    done = start_and_stop(bin_, environment(run, **settings), run.parent)
    assert done.returncode == 2, done.stdout + done.stderr
    assert "UserSide: started" not in done.stdout
    return done


def foreign_directory(tmp_path: Path) -> Path:
    """A directory owned by another user: made and given to nobody when we are root, else one
    root owns."""
    if os.geteuid() != 0:
        return Path("/")
    found = tmp_path / "theirs"
    found.mkdir(mode=0o700)
    os.chown(found, NOBODY, NOBODY)
    return found


def test_a_run_directory_owned_by_another_user_is_refused(bin_: Path, tmp_path: Path):
    run = foreign_directory(tmp_path)
    done = refused(bin_, run)
    owner = run.stat().st_uid
    assert (
        f"UserSide-start: the run directory {run} belongs to user id {owner}, not to you "
        f"({os.geteuid()}): not used" in done.stderr
    ), done.stderr
    assert "set ACORDCS_RUN_DIR to a directory of yours" in done.stderr


@pytest.mark.parametrize("permissions", [0o777, 0o770, 0o702, 0o1777])
def test_a_run_directory_others_can_write_is_refused(bin_: Path, tmp_path: Path, permissions):
    run = tmp_path / "run"
    run.mkdir()
    run.chmod(permissions)
    (run / "token").write_text("planted-by-someone")
    done = refused(bin_, run)
    assert f"the run directory {run} can be written by others" in done.stderr, done.stderr
    assert "chmod go-w" in done.stderr
    assert not (run / "UserSide.log").exists()


def test_a_run_directory_that_is_a_symbolic_link_is_refused(bin_: Path, tmp_path: Path):
    real = tmp_path / "real"
    real.mkdir(mode=0o700)
    link = tmp_path / "run"
    link.symlink_to(real)
    done = refused(bin_, link)
    assert f"the run directory {link} is a symbolic link: not used" in done.stderr, done.stderr
    assert not any(real.iterdir())


def test_the_default_directory_squatted_by_another_user_is_refused(bin_: Path, tmp_path: Path):
    if os.geteuid() != 0:
        pytest.skip("making a directory another user owns needs root")
    xdg = tmp_path / "xdg"
    xdg.mkdir(mode=0o755)
    squat = xdg / f"acordcs-{os.getuid()}"
    squat.mkdir(mode=0o777)
    os.chown(squat, NOBODY, NOBODY)
    done = start_and_stop(bin_, environment(None, XDG_RUNTIME_DIR=str(xdg)), tmp_path)
    assert done.returncode == 2 and f"the run directory {squat} belongs to user id" in done.stderr
    assert list(squat.iterdir()) == []


def private_run(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    run.mkdir(mode=0o700)
    return run


@pytest.mark.parametrize("permissions", [0o644, 0o640, 0o666, 0o400, 0o700])
def test_a_token_file_not_mode_0600_is_refused(bin_: Path, tmp_path: Path, permissions: int):
    run = private_run(tmp_path)
    token = run / "token"
    token.write_text("0123456789abcdef0123456789abcdef")
    token.chmod(permissions)
    done = refused(bin_, run)
    assert f"the token file {token} is not a regular file with mode 0600" in done.stderr
    assert "remove it (a new one is made) or set ACORDCS_TOKEN" in done.stderr


def test_a_token_file_of_another_user_is_refused(bin_: Path, tmp_path: Path):
    if os.geteuid() != 0:
        pytest.skip("giving a file to another user needs root")
    run = private_run(tmp_path)
    token = run / "token"
    token.write_text("0123456789abcdef0123456789abcdef")
    token.chmod(0o600)
    os.chown(token, NOBODY, NOBODY)
    done = refused(bin_, run)
    assert f"the token file {token} belongs to user id {NOBODY}, not to you" in done.stderr


def test_a_token_file_that_is_a_link_is_refused(bin_: Path, tmp_path: Path):
    run = private_run(tmp_path)
    theirs = tmp_path / "theirs-token"
    theirs.write_text("chosen-by-someone-else")
    theirs.chmod(0o600)
    (run / "token").symlink_to(theirs)
    done = refused(bin_, run)
    assert "is not a regular file with mode 0600" in done.stderr


def token(bin_: Path, env: dict[str, str]) -> subprocess.CompletedProcess:
    """The token the scripts use with ``env`` (env.sh sourced as they source it)."""
    return subprocess.run(
        ["sh", "-c", '. "$bin/env.sh" && printf %s "$ACORDCS_TOKEN"'],
        env={**env, "bin": str(bin_)},
        capture_output=True,
        text=True,
    )


def test_the_users_own_token_file_is_used_and_the_environment_wins(bin_: Path, tmp_path: Path):
    run = private_run(tmp_path)
    (run / "token").write_text("mine-0123456789\n")
    (run / "token").chmod(0o600)
    env = environment(run)
    assert token(bin_, env).stdout == "mine-0123456789"
    given = token(bin_, {**env, "ACORDCS_TOKEN": "from-the-environment"})
    assert given.stdout == "from-the-environment"


def test_an_empty_token_file_is_refused(bin_: Path, tmp_path: Path):
    run = private_run(tmp_path)
    (run / "token").write_text("")
    (run / "token").chmod(0o600)
    done = refused(bin_, run)
    assert f"the token file {run}/token is empty" in done.stderr
