"""Helpers of the generator tests: building a model into a directory, snapshots of a directory,
targets registered for one test, a target context made by hand."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

from acordcs.descriptor import Application, to_xml
from acordcs.generator import Target
from acordcs.generator import targets as builtin
from acordcs.generator.target_context import TargetContext
from tests.support.toolchain import WEBLAB, CliResult, replace, run_main


def build(model: Path | str, output: Path, *args: str) -> CliResult:
    """``acordcs-gen build MODEL -o OUTPUT ARGS...`` in-process."""
    return run_main(["build", str(model), "-o", str(output), *args])


def snapshot(directory: Path) -> dict[str, tuple[bytes, int]]:
    """Every file under ``directory`` (relative path -> bytes and mtime_ns)."""
    return {
        p.relative_to(directory).as_posix(): (p.read_bytes(), p.stat().st_mtime_ns)
        for p in sorted(directory.rglob("*"))
        if p.is_file()
    }


def weblab_variant(tmp_path: Path, *edits: tuple, name: str = "weblab.xmi") -> Path:
    """A copy of the WebLab model with each ``(old, new[, count])`` replaced (``old`` must occur
    ``count`` times, default once)."""
    text = WEBLAB.read_text(encoding="utf-8")
    for old, new, *count in edits:
        text = replace(text, old, new, *count)
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@contextlib.contextmanager
def registered(*targets: Target) -> Iterator[None]:
    """The built-in targets plus ``targets`` (made by the decorators), for the block only: the
    process's table of targets is one with these added, as an entry point would add them."""
    saved = builtin.TARGETS
    builtin.TARGETS = builtin.table(extra={t.name: t for t in targets})
    try:
        yield
    finally:
        builtin.TARGETS = saved


def context(app: Application, tmp_path: Path, target: str = "rules", source: str = "m.xmi"):
    """A TargetContext over ``app`` (its workdir under ``tmp_path``)."""
    workdir = tmp_path / f"work-{target}"
    workdir.mkdir(exist_ok=True)
    return TargetContext(target, app, to_xml(app), source, workdir)


FASTER = (
    "largeNarrow: if cycleRate is large and angle is narrow then Locomotion.maxSpeed is fast",
    "largeNarrow: if cycleRate is large and angle is narrow then Locomotion.maxSpeed is medium",
    2,
)
"""An edit of the WebLab model changing one rule of SpeedLimiting (in both of BOUML's places)."""


@contextlib.contextmanager
def imported(directory: Path, package: str) -> Iterator[object]:
    """The generated package ``package`` of ``directory`` imported in this process for the block
    (``directory`` first on sys.path); its modules are forgotten afterwards, so that the next
    build's package of the same name is imported afresh."""
    import importlib
    import sys

    def forget() -> None:
        for name in [m for m in sys.modules if m == package or m.startswith(package + ".")]:
            del sys.modules[name]

    forget()
    sys.path.insert(0, str(directory))
    importlib.invalidate_caches()
    try:
        yield importlib.import_module(package)
    finally:
        sys.path.remove(str(directory))
        forget()


def python_files(directory: Path) -> dict[str, str]:
    """Every ``.py`` file under ``directory``: relative path -> text."""
    return {
        p.relative_to(directory).as_posix(): p.read_text(encoding="utf-8")
        for p in sorted(directory.rglob("*.py"))
    }


def run_container(directory: Path, module: str, *args: str, timeout: float = 60):
    """``python -m MODULE ARGS...`` (a generated container module) with ``directory`` and the
    repository's ``src`` on PYTHONPATH, in ``directory``: the CompletedProcess (text)."""
    import os
    import subprocess
    import sys

    from tests.support.toolchain import ROOT

    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(directory), str(ROOT / "src")]))
    return subprocess.run(
        [sys.executable, "-m", module, *args],
        cwd=directory,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
