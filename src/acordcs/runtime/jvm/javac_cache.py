"""The Java components' classes at a container's start: the build's, else compiled by ``javac``
once per version of their sources into the private cache.

The build compiles them when it finds a JDK (``java-classes/<digest>/`` beside ``java/``:
:mod:`acordcs.javac`); a start whose sources have that digest loads those and needs no JDK.
Otherwise (no JDK at build time, or a source changed since) the start compiles them into the
private cache directory (:func:`acordcs.cachedir.private_dir`, under ``java/``), in a directory
named by the digest of the sources and of the ``javac`` used (its real path, size and time): a
start with unchanged sources compiles nothing, a change compiles afresh into a new directory.
Without a private cache directory the classes go to a temporary one, removed when the process
exits. A source that does not compile is a :class:`~.errors.JavaHostError` with javac's
``file:line`` and message, naming the component.
"""

from __future__ import annotations

import atexit
import hashlib
import os
import shutil
import tempfile
from collections.abc import Iterable
from pathlib import Path

from acordcs.cachedir import private_dir
from acordcs.javac import (
    JDK_HINT,
    JavacError,
    built_classes,
    compile_into,
    find_javac,
    source_digest,
)
from acordcs.runtime.jvm.errors import JavaHostError


def javac_identity(javac: str) -> str:
    """Which javac: its real path, size and modification time (running ``javac -version`` would
    cost every start a JVM's start)."""
    real = os.path.realpath(javac)
    info = os.stat(real)
    return f"{real} {info.st_size} {info.st_mtime_ns}"


def compiled_classes(sources: Path, roots: Iterable[Path], components: str) -> Path:
    """The directory of the compiled classes of ``sources`` (a ``java`` target's output), the
    user classes ``roots`` and what they use: the build's, else from the cache, else compiled
    now. ``components`` names the components they are, for the errors."""
    try:
        digest = source_digest(sources)
    except OSError as err:
        raise JavaHostError(
            f"{components} tagged language=java: cannot read its sources under {sources}: {err}",
            hint="rebuild the application (acordcs-gen build, with the java target)",
        ) from None
    built = built_classes(sources, digest)
    if built is not None:
        return built
    javac = find_javac()
    if javac is None:
        raise JavaHostError(
            f"{components} tagged language=java: its classes must be compiled at start (the "
            "build compiled none for these sources), and no javac is on PATH",
            hint=JDK_HINT + "; or build the application where a JDK is",
        )
    version = javac_identity(javac)
    key = hashlib.sha256(f"{digest}\0{version}".encode()).hexdigest()[:32]
    cache = private_dir()
    if cache is None:
        parent = Path(tempfile.mkdtemp(prefix="acordcs-java-"))
        atexit.register(shutil.rmtree, parent, True)
    else:
        parent = Path(cache) / "java"
        parent.mkdir(mode=0o700, exist_ok=True)
    try:
        return compile_into(parent, key, javac, sources, roots, version)
    except JavacError as err:
        hint = f"{err.hint}, then start again" if err.line else err.hint
        said = f":\n{err.said}" if err.said else ""
        raise JavaHostError(
            f"{components}: {err.message}{said}", file=err.file, line=err.line, hint=hint
        ) from None
