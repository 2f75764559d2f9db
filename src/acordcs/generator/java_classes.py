"""The build's last step when it built the ``java`` target: the classes of the components tagged
``language=java`` compiled into the output's ``java-classes/<digest>/`` (:mod:`acordcs.javac`:
the digest of the sources under ``java/``), where a container's start finds them and needs no
JDK. After the files are written: javac reads them there. Nothing Java runs.

Unchanged sources compile nothing (their directory is complete already); a change compiles a new
directory, and the directories of older sources are removed but the newest one before it (a
container still running those classes may yet load one of them). Without a JDK the build says so
in a note, and each start compiles them as before. A class that does not compile is the build's
error (exit 1) at javac's ``file:line``: the files written stay, as the model makes them, and no
classes are made for these sources (a start then finds the same error).
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from acordcs.javac import BUILT, COMPLETE, JavacError, compile_into, find_javac, source_digest

if TYPE_CHECKING:
    from acordcs.descriptor import Application
    from acordcs.generator.manifest import Manifest


@dataclass
class JavaBuild:
    """What the step did: ``classes`` (relative to the output) compiled or found complete,
    ``note`` (no JDK: compiled at start instead), ``error`` (a class that does not compile)."""

    classes: str = ""
    compiled: bool = False
    note: str = ""
    error: JavacError | None = None


def compile_java_classes(out: Path, app: Application, manifest: Manifest) -> JavaBuild | None:
    """Compile the classes of ``app``'s Java components in ``out`` (their user classes: the
    ``java`` target's files written once for them, by the manifest); None: it has none."""
    java = {c.id: c.name for c in app.components if c.language == "java"}
    roots = sorted(
        (rel, java[entry.ids[0]])
        for rel, entry in manifest.files.items()
        if entry.target == "java" and entry.user and entry.ids and entry.ids[0] in java
    )
    if not roots:
        return None
    names = ", ".join(name for _rel, name in roots)
    what = f"component{'s' if len(roots) > 1 else ''} {names} (tagged language=java)"
    sources = out / "java"
    parent = out / BUILT
    try:
        digest = source_digest(sources)
    except OSError as err:
        return JavaBuild(error=JavacError(f"{what}: cannot read the sources: {err}"))
    done = JavaBuild(classes=f"{BUILT}/{digest}")
    if (parent / digest / COMPLETE).is_file():
        return done  # compiled by an earlier build: nothing to do, JDK or not
    javac = find_javac()
    if javac is None:
        return JavaBuild(
            note=f"no javac on PATH: the Java classes of {what} are not compiled by the build; "
            "each container hosting them compiles them at start (install a JDK 17 or later to "
            "compile them here)"
        )
    try:
        parent.mkdir(exist_ok=True)
    except OSError as err:
        return JavaBuild(error=JavacError(f"{what}: cannot make {parent}: {err}"))
    done.compiled = True
    try:
        compile_into(parent, digest, javac, sources, [out / rel for rel, _ in roots], javac)
    except JavacError as err:
        err.message = f"{what}: {err.message}"
        done.error = err
        done.compiled = False
        return done
    _prune(parent, digest)
    return done


def _prune(parent: Path, current: str) -> None:
    """Remove the directories of classes but ``current`` and the newest one before it."""
    others = sorted(
        (p for p in parent.iterdir() if p.name != current and (p / COMPLETE).is_file()),
        key=lambda p: (p / COMPLETE).stat().st_mtime_ns,
        reverse=True,
    )
    for old in others[1:]:
        shutil.rmtree(old, ignore_errors=True)
