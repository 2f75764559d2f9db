"""The generated scripts run the Python that ran the build (``sys.executable``), named in the
header of ``bin/env.sh``; ``PYTHON`` overrides it. The interpreter is part of the ``shell``
target's fingerprint: a build by another interpreter writes ``env.sh`` again, instead of calling
the output up to date (issue 21, item 3: before, ``PYTHON`` defaulted to ``python3``, and outside
an activated virtual environment ``start-all`` failed with "No module named 'acordcs'")."""

from __future__ import annotations

import os
import site
import subprocess
import sys
from pathlib import Path

from tests.support.codegen import build
from tests.support.scripts import environment
from tests.support.toolchain import ROOT, WEBLAB


def python_of(bin_: Path, **settings: str) -> str:
    """``$PYTHON`` once ``bin/env.sh`` is sourced with ``settings``."""
    env = environment(None)
    del env["PYTHON"]
    env.update(settings)
    done = subprocess.run(
        ["sh", "-c", '. "$bin/env.sh" && printf %s "$PYTHON"'],
        env={**env, "bin": str(bin_)},
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_scripts_default_to_the_building_interpreter(tmp_path: Path):
    assert build(WEBLAB, tmp_path, "-t", "shell").code == 0
    bin_ = tmp_path / "bin"
    header = (bin_ / "env.sh").read_text(encoding="utf-8").splitlines()[3]
    assert header == (
        f"# Interpreter: {sys.executable}, the one that ran the build (PYTHON overrides it)."
    )
    assert python_of(bin_, TMPDIR=str(tmp_path)) == sys.executable
    assert python_of(bin_, TMPDIR=str(tmp_path), PYTHON="/opt/py/bin/python3") == (
        "/opt/py/bin/python3"
    )


def test_a_build_by_another_interpreter_writes_env_sh_again(tmp_path: Path):
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-t", "shell").code == 0
    other = tmp_path / "other" / "python"
    other.parent.mkdir()
    other.symlink_to(sys.executable)  # another path to this interpreter: sys.executable is it
    path = os.pathsep.join([str(ROOT / "src"), *site.getsitepackages()])
    done = subprocess.run(
        [str(other), "-c", "from acordcs.cli import run; run()", "build", str(WEBLAB), "-o",
         str(out), "-t", "shell"],
        env={**os.environ, "PYTHONPATH": path},
        capture_output=True,
        text=True,
        timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"wrote {out}/bin/env.sh" in done.stdout and "1 written" in done.stdout, done.stdout
    env = (out / "bin" / "env.sh").read_text(encoding="utf-8")
    assert f"[ -n \"${{PYTHON-}}\" ] || PYTHON='{other}'\n" in env
