"""A container module's ``--run COMPONENT.OPERATION``: the operation is called through the
container once it serves (on a virtual clock in turn, before the duration runs), its result or its
failure is reported in one line (a failure: exit 1, the message saying what to implement), a name
that is not hosted is a usage error (exit 2) naming what is, and the ``shell`` target passes
``ACORDCS_<Container>_RUN`` (blank-separated) as ``--run`` options."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support import scripts
from tests.support.generator import build
from tests.support.toolchain import ROOT, WEBLAB

REMOTE = ("--remote", "WebLabSide=PYRO:acordcs.container.WebLabSide@127.0.0.1:9")

# The Navigator's run() sleeps 2 virtual seconds, then returns what step() gives; step() counts
# how often it was called and returns the count: the container sees both calls (its stats).
NAVIGATOR = """
from weblab_app.base.Navigator import NavigatorBase


class Navigator(NavigatorBase):
    steps = 0

    def run(self):
        self.clock.sleep(2.0)
        return "done"

    def step(self):
        type(self).steps += 1
        return type(self).steps
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("run") / "out"
    result = build(WEBLAB, out, "-t", "python,shell")
    assert result.code == 0, result.both
    return out


def module(directory: Path, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(directory), str(ROOT / "src")]))
    return subprocess.run(
        [sys.executable, "-m", "weblab_app.UserSide", *REMOTE, *args],
        cwd=directory,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )


def test_the_help_names_the_option(built: Path) -> None:
    done = module(built, "--help")
    assert done.returncode == 0, done.stderr
    assert "--run COMPONENT.OPERATION" in done.stdout


def test_an_operation_without_code_fails_with_a_message_and_exit_1(built: Path) -> None:
    done = module(built, "--run", "Navigator.run", "--duration", "3")
    assert done.returncode == 1, done.stdout + done.stderr
    lines = done.stderr.splitlines()
    (line,) = [x for x in lines if x.startswith("python -m weblab_app.UserSide: --run")]
    assert line.startswith(
        "python -m weblab_app.UserSide: --run Navigator.run() failed at t=0.000 s"
    )
    assert "implement run() in components/Navigator.py" in line
    # It stopped at the failure, not after the duration.
    assert done.stdout.splitlines()[-1] == "UserSide: stopped at t=0.000 s, faults: 1"


@pytest.mark.parametrize(
    ("spec", "says"),
    [
        ("Nav.run", "container UserSide hosts no component 'Nav' (it hosts: Navigator)"),
        ("Navigator.fly", "component 'Navigator' has no operation 'fly' (operations: "),
        ("Navigator", "'Navigator' is not COMPONENT.OPERATION"),
    ],
)
def test_a_name_not_hosted_here_is_a_usage_error(built: Path, spec: str, says: str) -> None:
    done = module(built, "--run", spec)
    assert done.returncode == 2, done.stdout + done.stderr
    assert says in done.stderr
    assert "Traceback" not in done.stderr
    assert "serving at" not in done.stdout


def test_operations_run_in_turn_through_the_container(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-t", "python").code == 0
    (out / "weblab_app" / "components" / "Navigator.py").write_text(NAVIGATOR, encoding="utf-8")
    done = module(
        out, "--run", "Navigator.step", "--run", "Navigator.run", "--run", "Navigator.step",
        "--duration", "5",
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.splitlines() == [
        "UserSide: --run Navigator.step() returned 1 at t=0.000 s",
        "UserSide: --run Navigator.run() returned 'done' at t=2.000 s",
        "UserSide: --run Navigator.step() returned 2 at t=2.000 s",
        "UserSide: stopped at t=5.000 s, faults: 0",
    ]


def test_a_real_clock_runs_the_operation_in_a_worker_while_it_serves(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-t", "python").code == 0
    (out / "weblab_app" / "components" / "Navigator.py").write_text(NAVIGATOR, encoding="utf-8")
    done = module(out, "--clock", "real", "--duration", "3", "--serve", "0",
                  "--host", "127.0.0.1", "--run", "Navigator.run")  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    assert lines[0].startswith("UserSide: serving at PYRO:acordcs.container.UserSide@127.0.0.1:")
    assert lines[1].startswith("UserSide: runs descriptor sha256 ")  # what acordcs-gen update reads
    assert lines[2].startswith("UserSide: --run Navigator.run() returned 'done' at t=2.")
    assert lines[3].startswith("UserSide: stopped at t=3.")


def test_the_start_script_passes_the_environment_variable_as_run_options(tmp_path: Path) -> None:
    assert scripts.run_options_passed(tmp_path, "Navigator.run  Navigator.step") == [
        "Navigator.run",
        "Navigator.step",
    ]
