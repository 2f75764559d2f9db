"""A generated application runs on the runtime and the leaf packages it needs (the descriptor, the
rule grammar, the errors), never on the toolchain: each container of both samples, run as the
scripts run it (``python -m <package>.<Container>``), ends with no module of ``acordcs.xmi``,
``.model``, ``.profile``, ``.generator``, ``.cli`` or ``.metamodel`` loaded, nor the toolchain's own
libraries (pyecore, saxonche, click)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.generator import build
from tests.support.toolchain import SAMPLES, SMARTROOM, WEBLAB

TOOLCHAIN = (
    *(f"acordcs.{p}" for p in ("xmi", "model", "profile", "generator", "cli", "metamodel")),
    "pyecore",
    "saxonche",
    "click",
)

# Runs one container module as ``python -m`` does and prints the modules loaded when it ends.
PROBE = """
import json, runpy, sys
sys.argv = [sys.argv[1], *sys.argv[2:]]
try:
    runpy.run_module(sys.argv[0], run_name="__main__", alter_sys=True)
except SystemExit as stop:
    code = stop.code
else:
    code = 0
print(json.dumps({"code": code, "modules": sorted(sys.modules)}))
"""


def containers(app: Path, package: str) -> list[str]:
    descriptor = (app / package / "descriptor.xml").read_text(encoding="utf-8")
    from acordcs.descriptor import from_xml

    return [c.name for c in from_xml(descriptor.encode()).containers]


@pytest.mark.parametrize(
    ("model", "package", "extra"),
    [(WEBLAB, "weblab_app", SAMPLES / "weblab"), (SMARTROOM, "smartroom_app", None)],
    ids=["weblab", "smartroom"],
)
def test_each_container_runs_without_the_toolchain(model, package, extra, tmp_path: Path):
    out = tmp_path / "app"
    if extra is not None:  # the WebLab's own code: its user classes and its simulator
        shutil.copytree(extra / "app", out)
    assert build(model, out, "--target", "python").code == 0
    path = [str(out)] + ([str(extra)] if extra is not None else [])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(path), "ACORDCS_TOKEN": "t" * 32}
    names = containers(out, package)
    assert names
    for container in names:
        # The others at a port nothing serves: calls to them fail, as faults of a running container.
        others = [
            f"--remote={o}=PYRO:acordcs.container.{o}@127.0.0.1:9" for o in names if o != container
        ]
        done = subprocess.run(
            [sys.executable, "-c", PROBE, f"{package}.{container}", "--duration", "2", *others],
            capture_output=True,
            text=True,
            env=env,
            cwd=tmp_path,
            timeout=120,
        )
        last = done.stdout.strip().splitlines()[-1]
        report = json.loads(last)
        assert report["code"] != 2, done.stderr  # it started (faults may follow: see above)
        assert f"{container}: stopped at t=2.000 s" in done.stdout, done.stdout + done.stderr
        loaded = [m for m in report["modules"] if m.startswith(TOOLCHAIN)]
        assert loaded == [], f"{container} loaded {loaded}"
        assert package in report["modules"]
