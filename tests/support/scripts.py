"""Helpers of the ``shell`` target's script tests: the WebLab's scripts built over a stand-in
package (:mod:`tests.support.fake_container`), run in a clean environment; harmless processes to
forge pid files with; a PID namespace to try what could signal every process."""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support import fake_container
from tests.support.generator import build
from tests.support.toolchain import WEBLAB

PACKAGE = "weblab_app"
CONTAINERS = ("UserSide", "WebLabSide")


def built(out: Path) -> Path:
    """The WebLab's ``shell`` target built into ``out`` with the stand-in package beside it;
    returns ``out / "bin"``."""
    result = build(WEBLAB, out, "-t", "shell")
    assert result.code == 0, result.both
    fake_container.install(out, PACKAGE, CONTAINERS)
    return out / "bin"


def environment(run: Path | None, **settings: str) -> dict[str, str]:
    """The caller's environment without any ACORDCS_ or FAKE_ setting, with ``PYTHON`` this
    interpreter, ``ACORDCS_RUN_DIR`` ``run`` (None: unset, the scripts' default) and
    ``settings``."""
    env = {
        k: v
        for k, v in os.environ.items()
        if not k.startswith(("ACORDCS_", "FAKE_")) and k != "XDG_RUNTIME_DIR"
    }
    env["PYTHON"] = sys.executable
    if run is not None:
        env["ACORDCS_RUN_DIR"] = str(run)
    env.update(settings)
    return env


def script(
    bin_: Path, name: str, env: dict[str, str], *args: str, timeout: float = 60
) -> subprocess.CompletedProcess:
    """``sh bin/NAME ARGS...`` (its output as text)."""
    return subprocess.run(
        ["sh", str(bin_ / name), *args], env=env, capture_output=True, text=True, timeout=timeout
    )


def alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    state = subprocess.run(["ps", "-o", "stat=", "-p", str(pid)], capture_output=True, text=True)
    return state.stdout.strip() != "" and not state.stdout.strip().startswith("Z")


def wait_until(condition, what: str, timeout: float = 30) -> None:
    """Polls ``condition()`` until it is true; fails naming ``what`` after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"not within {timeout} s: {what}"
        time.sleep(0.05)


@contextlib.contextmanager
def process(*argv: str, new_session: bool = False) -> Iterator[subprocess.Popen]:
    """A harmless process of ours (``argv``), killed and reaped at the end of the block."""
    proc = subprocess.Popen(
        list(argv),
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=new_session,
    )
    try:
        wait_until(lambda: alive(proc.pid), f"{argv} running", 10)
        yield proc
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=10)


def sleeper(new_session: bool = False):
    """An unrelated process of this user: ``sleep 300``."""
    return process("sleep", "300", new_session=new_session)


def pid_namespace() -> list[str]:
    """The command prefix that runs a command as process 1 of a new PID namespace with its own
    /proc (as root, or as this user mapped to root in a user namespace); skips the test (fails it
    when CI=true) where the system allows neither."""
    found = shutil.which("unshare")
    tries = [] if found is None else [[found, "--pid", "--fork", "--mount-proc"]]
    tries += (
        []
        if found is None
        else [[found, "--user", "--map-root-user", "--pid", "--fork", "--mount-proc"]]
    )
    for prefix in tries:
        done = subprocess.run([*prefix, "true"], capture_output=True, timeout=30)
        if done.returncode == 0:
            return prefix
    reason = "cannot make a PID namespace here (unshare from util-linux, and user namespaces)"
    if os.environ.get("CI") == "true":
        pytest.fail(f"the PID namespace test cannot run in CI: {reason}")
    pytest.skip(reason)


def run_options_passed(tmp_path: Path, run: str) -> list[str]:
    """The ``--run`` options ``bin/UserSide-start`` gives the container module when
    ``ACORDCS_UserSide_RUN`` is ``run`` (the WebLab built into ``tmp_path``; a stand-in module,
    tests.support.fake_container, records its arguments)."""
    bin_ = built(tmp_path / "out")
    args = tmp_path / "args"
    env = environment(tmp_path / "run", FAKE_ARGS=str(args), ACORDCS_UserSide_RUN=run)
    try:
        started = script(bin_, "UserSide-start", env)
        assert started.returncode == 0, started.stdout + started.stderr
    finally:
        script(bin_, "UserSide-stop", env)
    given = args.read_text().split("\0")
    return [given[i + 1] for i, a in enumerate(given) if a == "--run"]
