"""Compiling the classes of the components tagged ``language=java`` with ``javac``: what the
build does when a JDK is present (``acordcs-gen build``, into the application's
``java-classes/<digest>/``) and what a container's start does otherwise (into the private cache:
:mod:`acordcs.runtime.jvm.javac_cache`). One digest names both: :func:`source_digest`, of every
``.java`` file of the ``java`` target's output (path and bytes), so that a start finds the
build's classes for the sources it has, and compiles afresh only when a source changed.

``javac`` compiles the user classes of the Java components (``java/<package>/<C>.java``) and
what they use (``-sourcepath``: their generated bases, the Java API), for Java 17
(``--release 17``: the classes load in any JVM from 17 on, whichever JDK compiled them), with
no annotation processing (``-proc:none``) and only its output directory as class path (no class
of the working directory or ``$CLASSPATH`` is taken instead of a source): no Java code of the
application runs. A source that does not compile is a :class:`JavacError` at javac's first
``file:line``, with its message.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterable
from pathlib import Path

from acordcs.errors import AcordError

JDK_HINT = (
    "install a JDK 17 or later (Debian, Ubuntu: apt-get install openjdk-17-jdk-headless) so that "
    "javac and the JVM are found, or tag the component language=python"
)
BUILT = "java-classes"
"""The directory, beside ``java/``, of the classes the build compiled (one per digest)."""
COMPLETE = ".complete"
"""The file that makes a directory of classes complete (written last, before its rename)."""
COMPILE_TIMEOUT = 300.0  # seconds: javac of a few classes takes about one
RELEASE = "17"
_ERROR = re.compile(r"^(?P<file>.+?\.java):(?P<line>\d+): error: (?P<message>.*)$")


class JavacError(AcordError):
    """javac is missing, failed, or found an error (``file`` and ``line``: javac's first);
    ``said``: javac's whole output when it found more than one."""

    said = ""


def source_digest(sources: Path) -> str:
    """The digest naming the compiled classes of ``sources``: its ``.java`` files, path and
    bytes (OSError when one cannot be read)."""
    digest = hashlib.sha256()
    for path in sorted(sources.rglob("*.java")):
        digest.update(path.relative_to(sources).as_posix().encode() + b"\0")
        digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()[:32]


def built_classes(sources: Path, digest: str) -> Path | None:
    """The build's complete classes of the sources of digest ``digest`` (``sources``: the
    ``java`` target's output), or None."""
    found = sources.parent / BUILT / digest
    return found if (found / COMPLETE).is_file() else None


def find_javac() -> str | None:
    return shutil.which("javac")


def compile_into(
    parent: Path, name: str, javac: str, sources: Path, roots: Iterable[Path], stamp: str
) -> Path:
    """``parent/name``, holding the classes of the user classes ``roots`` of ``sources`` and what
    they use: made now unless complete already. Compiled beside it, then renamed: a reader sees a
    complete directory or none. ``stamp``: what ``.complete`` says (which javac)."""
    final = parent / name
    if (final / COMPLETE).is_file():
        return final
    work = Path(tempfile.mkdtemp(prefix=f".{name}.", dir=parent))
    try:
        run_javac(javac, sources, list(roots), work)
        (work / COMPLETE).write_text(stamp + "\n", encoding="utf-8")
        try:
            os.rename(work, final)
        except OSError:  # another process made it meanwhile: theirs is as good
            if not (final / COMPLETE).is_file():
                raise
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return final


def run_javac(javac: str, sources: Path, roots: list[Path], out: Path) -> None:
    """Compile ``roots`` (and what they use, from ``sources``) into ``out``; JavacError."""
    command = [javac, "--release", RELEASE, "-encoding", "UTF-8", "-nowarn", "-implicit:class",
               "-proc:none", "-classpath", str(out), "-sourcepath", str(sources), "-d", str(out),
               *map(str, roots)]  # fmt: skip
    try:
        done = subprocess.run(
            command, capture_output=True, text=True, timeout=COMPILE_TIMEOUT, check=False
        )
    except subprocess.TimeoutExpired:
        raise JavacError(f"javac did not finish in {COMPILE_TIMEOUT:g} s", hint=JDK_HINT) from None
    except OSError as err:
        raise JavacError(f"javac ({javac}) did not run: {err}", hint=JDK_HINT) from None
    if done.returncode == 0:
        return
    said = (done.stderr or done.stdout).strip()
    errors = [found for line in said.splitlines() if (found := _ERROR.match(line))]
    if not errors:
        raise JavacError(f"javac failed: {said}", hint=JDK_HINT)
    first = errors[0]
    more = f" (and {len(errors) - 1} more error(s), below)" if len(errors) > 1 else ""
    error = JavacError(
        f"its Java class does not compile: {first['message']}{more}",
        file=first["file"],
        line=int(first["line"]),
        hint="fix the Java source there (java/<package>/<Component>.java is yours)",
    )
    if len(errors) > 1:
        error.said = said
    raise error
