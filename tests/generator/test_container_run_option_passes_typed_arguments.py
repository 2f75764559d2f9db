"""A container module's ``--run 'COMPONENT.OPERATION(ARGUMENTS)'`` calls the operation with its
arguments typed by the model's parameters (the WebLab's ``Access.authenticate(user: string, token:
string)``, ``PanoramicCamera.setFrameRate(rate: int)``, ``Locomotion.move(speed: double, turn:
double)``), and prints the call as made. A value that does not fit, too many or too few
arguments, code, NaN, a number of a hundred thousand digits: exit 2 with what, which parameter
and what to write, before anything starts (no component's ``on_start`` ran, nothing served,
nothing evaluated). The start script passes ``ACORDCS_<Container>_RUN``'s calls with their
arguments as they are."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support import scripts
from tests.support.generator import build
from tests.support.toolchain import ROOT, WEBLAB

REMOTE = ("--remote", "UserSide=PYRO:acordcs.container.UserSide@127.0.0.1:9")

CODE = {
    "Access": """
from weblab_app.base.Access import AccessBase


class Access(AccessBase):
    def on_start(self):
        print("Access: on_start ran", flush=True)

    def authenticate(self, user, token):
        return f"{user}:{token}"
""",
    "PanoramicCamera": """
from weblab_app.base.PanoramicCamera import PanoramicCameraBase


class PanoramicCamera(PanoramicCameraBase):
    def setFrameRate(self, rate):
        return (type(rate).__name__, rate * 2)
""",
    "Locomotion": """
from weblab_app.base.Locomotion import LocomotionBase


class Locomotion(LocomotionBase):
    def move(self, speed, turn):
        return (speed, turn)
""",
}


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("run-args") / "out"
    assert build(WEBLAB, out, "-t", "python").code == 0
    for name, source in CODE.items():
        (out / "weblab_app" / "components" / f"{name}.py").write_text(source, encoding="utf-8")
    return out


def module(directory: Path, container: str, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(directory), str(ROOT / "src")]))
    remote = REMOTE if container == "WebLabSide" else ()
    return subprocess.run(
        [sys.executable, "-m", f"weblab_app.{container}", *remote, *args],
        cwd=directory,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )


def test_the_arguments_reach_the_operation_typed_by_the_model(built: Path) -> None:
    done = module(
        built, "WebLabSide", "--duration", "0.5",
        "--run", "Access.authenticate('ann', \"s3 cret\")",
        "--run", "PanoramicCamera.setFrameRate(rate=12)",
        "--run", "Locomotion.move(5, -0.5)",
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    runs = [line for line in done.stdout.splitlines() if ": --run " in line]
    assert runs == [
        "WebLabSide: --run Access.authenticate('ann', 's3 cret') returned 'ann:s3 cret' at t=0.000 s",
        "WebLabSide: --run PanoramicCamera.setFrameRate(12) returned ('int', 24) at t=0.000 s",
        "WebLabSide: --run Locomotion.move(5.0, -0.5) returned (5.0, -0.5) at t=0.000 s",
    ]


@pytest.mark.parametrize(
    ("spec", "says"),
    [
        ("PanoramicCamera.setFrameRate", "--run PanoramicCamera.setFrameRate: PanoramicCamera.setFrameRate(rate: int) takes 1 argument, 0 given: give rate (int), as PanoramicCamera.setFrameRate(5)"),
        ("PanoramicCamera.setFrameRate(1, 2)", "takes 1 argument, 2 given: give one value per parameter, in order"),
        ("PanoramicCamera.setFrameRate(2.5)", "argument 1 of setFrameRate, parameter rate (int): 2.5 is not an int: write a whole number (5, -3)"),
        ("Locomotion.move(nan, 0)", "argument 1 of move, parameter speed (double): nan is not a finite number: write a finite number"),
        ("Locomotion.move(5)", "takes 2 arguments, 1 given: give turn (double), as Locomotion.move(2.5, 2.5)"),
        ("Access.authenticate(ann, 'x')", "parameter user (string): 'ann' is not a value: write a number, true or false, or a string in quotes"),
        ("Access.authenticate(__import__('os').system('touch pwned'), 'x')", "is not a value: write a number, true or false, or a string in quotes (nothing is evaluated)"),
        ("PanoramicCamera.setFrameRate(" + "9" * 100_000 + ")", "characters: a --run has at most 4096"),
    ],
)  # fmt: skip
def test_arguments_that_do_not_fit_are_refused_before_anything_starts(
    built: Path, spec: str, says: str
) -> None:
    done = module(built, "WebLabSide", "--run", spec, "--serve", "0", "--host", "127.0.0.1")
    assert done.returncode == 2, done.stdout + done.stderr
    assert says in done.stderr
    assert "Traceback" not in done.stderr
    assert "on_start ran" not in done.stdout and "serving at" not in done.stdout
    assert not (built / "pwned").exists()


def test_a_parameter_of_a_model_class_cannot_be_given(built: Path) -> None:
    done = module(built, "UserSide", "--run", "Navigator.findStripe(1)")
    assert done.returncode == 2, done.stdout + done.stderr
    assert (
        "--run Navigator.findStripe(1): argument 1 of findStripe, parameter frame (Image): a "
        "value of type Image cannot be written on a command line" in done.stderr
    )


def test_the_start_script_passes_calls_with_their_arguments(tmp_path: Path) -> None:
    assert scripts.run_options_passed(tmp_path, "Display.watch(5) Display.show('*',2.5,true)") == [
        "Display.watch(5)",
        "Display.show('*',2.5,true)",
    ]


def test_the_build_pages_examples_are_what_it_prints(built: Path) -> None:
    page = (ROOT / "docs" / "build.md").read_text(encoding="utf-8")
    for spec in ("PanoramicCamera.setFrameRate(2.5)", "PanoramicCamera.setFrameRate"):
        done = module(built, "WebLabSide", "--run", spec)
        (line,) = done.stderr.splitlines()
        assert f"\n{line}\n" in page
