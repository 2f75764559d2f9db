"""At start, a container lists the operations of its components that have no code and that the
model calls (acordcs.runtime.live.code_check): a crisp rule of a policy set there, a polling monitor there,
a connection to a synchronous provided port (every operation of the component), a ``--run``. A
fresh WebLab build lists exactly those of the model; the WebLab's own code lists none; renaming
an operation in the model (issue 21's loop) names the new one, its caller and the user's file, and
``--strict`` then refuses to start."""

from __future__ import annotations

import inspect
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from acordcs.runtime.api import VirtualClock
from acordcs.runtime.errors import OperationNotImplementedError
from acordcs.runtime.live.code_check import operations_without_code
from tests.support.generator import build, imported, weblab_variant
from tests.support.toolchain import ROOT, WEBLAB

APP = WEBLAB.parent / "app" / "weblab_app"
URI = "PYRO:acordcs.container.{}@127.0.0.1:9"
LOCOMOTION = (
    "connection LocomotionLink reaches it from Navigator.NavLocomotionPort",
    "connection RecoveryLink reaches it from Recovery.RecoveryLocomotionPort",
)
# What the WebLab's model calls in the WebLab's container, read off the model by hand: its
# connections to synchronous provided ports (AccessLink, LocomotionLink, RecoveryLink,
# VisionLink), the Usage monitor polling countUsers, the Recovering set's rules calling recover()
# and askUser(). PanoramicCamera.setFrameRate has no caller (its port is a stream).
CALLED = [
    ("Access", "authenticate", ("connection AccessLink reaches it from Navigator.NavAccessPort",)),
    ("Access", "countUsers", ("monitor Usage polls it",
                              "connection AccessLink reaches it from Navigator.NavAccessPort")),
    ("Locomotion", "move", LOCOMOTION),
    ("Locomotion", "odometry", LOCOMOTION),
    ("Locomotion", "stop", LOCOMOTION),
    ("Recovery", "askUser", ("policy set Recovering calls it",)),
    ("Recovery", "recover", ("policy set Recovering calls it",)),
    ("Vision", "grab", ("connection VisionLink reaches it from Navigator.NavVisionPort",)),
]  # fmt: skip


def with_weblab_code(out: Path) -> Path:
    """``out`` holding the WebLab's own component and monitor code (a build keeps it)."""
    for part in ("components", "monitors"):
        (out / "weblab_app" / part).mkdir(parents=True)
        for source in (APP / part).glob("[A-Z]*.py"):
            shutil.copy(source, out / "weblab_app" / part / source.name)
    return out


def listed(out: Path, container: str, runs=()) -> list[tuple[str, str, tuple[str, ...]]]:
    other = "UserSide" if container == "WebLabSide" else "WebLabSide"
    with (
        imported(out, "weblab_app") as package,
        package.assemble_application(
            only=[container], remote={other: URI.format(other)}, clock=VirtualClock()
        ) as app,
    ):
        missing = operations_without_code(app, container, runs)
        # Each one listed has indeed no code: calling it raises.
        for item in missing:
            method = getattr(app.container(container).instance(item.component), item.operation)
            with pytest.raises(OperationNotImplementedError):
                method(*[None] * len(inspect.signature(method).parameters))
        return [(m.component, m.operation, m.callers) for m in missing]


def test_a_fresh_build_lists_what_the_model_calls(tmp_path: Path) -> None:
    assert build(WEBLAB, tmp_path, "-t", "python").code == 0
    assert listed(tmp_path, "WebLabSide") == CALLED
    assert listed(tmp_path, "UserSide") == []  # nothing calls the Navigator...
    assert listed(tmp_path, "UserSide", [("Navigator", "run")]) == [
        ("Navigator", "run", ("--run calls it",))  # ...but the command line
    ]


def test_the_weblabs_own_code_lists_nothing(tmp_path: Path) -> None:
    out = with_weblab_code(tmp_path / "out")
    assert build(WEBLAB, out, "-t", "python").code == 0
    sys.path.insert(0, str(WEBLAB.parent))  # weblab_sim, which the WebLab's code imports
    try:
        assert listed(out, "WebLabSide") == []
        assert listed(out, "UserSide", [("Navigator", "run")]) == []
    finally:
        sys.path.remove(str(WEBLAB.parent))


def test_a_renamed_operation_is_named_with_its_caller_and_strict_refuses(tmp_path: Path) -> None:
    out = with_weblab_code(tmp_path / "out")
    model = weblab_variant(tmp_path, ('"countUsers"', '"sampleUsers"', 3))
    assert build(model, out, "-t", "python").code == 0
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(out), str(WEBLAB.parent), str(ROOT / "src")]),
    }
    command = [sys.executable, "-m", "weblab_app.WebLabSide", "--strict",
               "--remote", f"UserSide={URI.format('UserSide')}"]  # fmt: skip
    done = subprocess.run(command, cwd=out, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stdout + done.stderr
    line = next(x for x in done.stderr.splitlines() if ": warning: " in x)
    source = (out / "weblab_app" / "components" / "Access.py").read_text(encoding="utf-8")
    class_line = source.splitlines().index("class Access(AccessBase):") + 1
    assert line == (
        f"weblab_app/components/Access.py:{class_line}: warning: Access.sampleUsers() has no "
        "code, and monitor Usage polls it; connection AccessLink reaches it from "
        "Navigator.NavAccessPort: implement sampleUsers() in class Access (each call raises "
        "OperationNotImplementedError until then)"
    )
    assert f"\n{line}\n" in (ROOT / "docs" / "build.md").read_text(encoding="utf-8")
    assert done.stderr.splitlines()[-1] == (
        "python -m weblab_app.WebLabSide: not started (--strict): 1 operation(s) that the model "
        "calls have no code (listed above)"
    )
    assert "serving at" not in done.stdout and "stopped at" not in done.stdout
