"""mypy --strict passes on the ``python`` target's packages: the WebLab's with the WebLab's own
component and monitor code (samples/weblab/app, which reads its properties as typed attributes,
without casts), and the SmartRoom's as a fresh build writes it. The typing is real: code that
misuses a typed property or overrides an operation with the wrong types fails the same check."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.generator import build
from tests.support.toolchain import SMARTROOM, WEBLAB

APP = WEBLAB.parent / "app" / "weblab_app"

# weblab_sim is the WebLab's simulator (its own typing is not what is checked here); serpent, which
# the Navigator uses to read bytes that crossed Pyro5, ships no type information.
CONFIG = """\
[mypy]
strict = True
cache_dir = {cache}

[mypy-weblab_sim.*]
follow_imports = silent

[mypy-serpent]
ignore_missing_imports = True
"""


@pytest.fixture(scope="module")
def config(tmp_path_factory) -> Path:
    where = tmp_path_factory.mktemp("mypy")
    path = where / "mypy.ini"
    path.write_text(CONFIG.format(cache=where / "cache"), encoding="utf-8")
    return path


def mypy(config: Path, directory: Path, package: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "MYPYPATH": str(WEBLAB.parent)}  # weblab_sim
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--config-file", str(config), "-p", package],
        cwd=directory,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def weblab_with_its_code(out: Path) -> Path:
    """The WebLab built into ``out`` with the component and monitor code of samples/weblab/app
    (copied there first: the build keeps a user's files)."""
    for part in ("components", "monitors"):
        (out / "weblab_app" / part).mkdir(parents=True)
        for source in (APP / part).glob("[A-Z]*.py"):
            shutil.copy(source, out / "weblab_app" / part / source.name)
    result = build(WEBLAB, out, "-t", "python")
    assert result.code == 0, result.both
    return out


@pytest.fixture(scope="module")
def weblab(tmp_path_factory) -> Path:
    return weblab_with_its_code(tmp_path_factory.mktemp("weblab"))


def test_the_weblab_with_its_own_code(config: Path, weblab: Path) -> None:
    done = mypy(config, weblab, "weblab_app")
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith("Success: no issues found in 26 source files")


def test_the_smartroom_as_built(config: Path, tmp_path: Path) -> None:
    result = build(SMARTROOM, tmp_path, "-t", "python")
    assert result.code == 0, result.both
    done = mypy(config, tmp_path, "smartroom_app")
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith("Success: no issues found")


MISUSE = """
from weblab_app import model_types
from weblab_app.base.Navigator import NavigatorBase
from weblab_app.base.Recovery import RecoveryBase


class Recovery(RecoveryBase):
    def recover(self) -> None:
        self.retries = "three"
        self.backupDistance.upper()


class Navigator(NavigatorBase):
    def step(self) -> str:
        return "yes"

    def findStripe(self, frame: bytes) -> float:
        return 0.0
"""


def test_misusing_the_types_fails(config: Path, weblab: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    shutil.copytree(weblab, out)
    (out / "weblab_app" / "components" / "misuse.py").write_text(MISUSE, encoding="utf-8")
    done = mypy(config, out, "weblab_app")
    assert done.returncode == 1, done.stdout
    found = {
        line.split(": error: ", 1)[1] for line in done.stdout.splitlines() if ": error: " in line
    }
    assert found == {
        'Incompatible types in assignment (expression has type "str", variable has type "int")  [assignment]',
        '"float" has no attribute "upper"  [attr-defined]',
        'Return type "str" of "step" incompatible with return type "bool" in supertype '
        '"weblab_app.base.Navigator.NavigatorBase"  [override]',
        'Argument 1 of "findStripe" is incompatible with supertype '
        '"weblab_app.base.Navigator.NavigatorBase"; supertype defines the argument type as '
        '"object"  [override]',
    }, done.stdout
