"""``build --check --strict`` fails on a user class that does not compile, as a container's start
refuses it: warning G705 at its ``file:line:col``, exit 1, where it said "up to date" (exit 0) and
CI passed an application that cannot start. Without ``--strict`` the warning is printed and the
exit code is the build's. A fixed class passes again. ``ulimit -v`` below what Saxon reserves is
said in words, not as ``graal_create_isolate error``."""

from __future__ import annotations

import resource
import subprocess
from pathlib import Path

import pytest

from tests.support.generator import build
from tests.support.toolchain import WEBLAB, entry_point


@pytest.fixture
def built(tmp_path: Path) -> Path:
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-q").code == 0
    return out


def test_a_class_that_does_not_compile_fails_check_strict(built: Path):
    cls = built / "weblab_app" / "components" / "Locomotion.py"
    cls.write_text(
        "class Locomotion(LocomotionBase):\n    def move(self, speed\n", encoding="utf-8"
    )
    strict = build(WEBLAB, built, "--check", "--strict")
    assert strict.code == 1, strict.both
    (line,) = [w for w in strict.out.splitlines() if "G705" in w]
    assert line.startswith(
        f"{cls}:2:13: warning: G705 class of component Locomotion does not compile"
    )
    assert "up to date" in strict.out  # the generated files are: the class is what fails
    plain = build(WEBLAB, built, "--check")
    assert plain.code == 0 and "G705" in plain.out, plain.both
    assert build(WEBLAB, built, "--strict").code == 1  # a build that writes says it too
    cls.write_text(
        "from weblab_app.base.Locomotion import LocomotionBase\n\n\nclass Locomotion(LocomotionBase):\n    pass\n",
        encoding="utf-8",
    )
    fixed = build(WEBLAB, built, "--check", "--strict")
    assert fixed.code == 0 and "G705" not in fixed.both, fixed.both


def test_a_monitor_class_and_an_indentation_error_too(built: Path):
    cls = built / "weblab_app" / "monitors" / "Control.py"
    cls.write_text("class Control:\npass\n", encoding="utf-8")
    strict = build(WEBLAB, built, "--check", "--strict")
    assert strict.code == 1, strict.both
    assert (
        f"{cls}:2:1: warning: G705 class of monitor Control does not compile: expected an indented block"
        in strict.out
    )


def test_strict_on_an_up_to_date_output_compiles_them_too(built: Path):
    cls = built / "weblab_app" / "components" / "Vision.py"
    cls.write_text("def (:\n", encoding="utf-8")
    done = build(WEBLAB, built, "--strict")  # nothing to build: the manifest says so
    assert "model unchanged, nothing written" in done.out
    assert done.code == 1 and f"{cls}:1:5: warning: G705" in done.out, done.both


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4 * 1024**3, resource.RLIM_INFINITY))


def test_an_address_space_limit_below_saxons_is_said_in_words(tmp_path: Path):
    done = subprocess.run(
        [*entry_point(), "build", str(WEBLAB), "-o", str(tmp_path / "out"), "-t", "java"],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=_limited,
        check=False,
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert "could not reserve its address space" in done.stderr
    assert "ulimit -v unlimited" in done.stderr
    assert "graal_create_isolate" not in done.stderr
    assert not (tmp_path / "out").exists()
