"""The Java components' classes, compiled by ``javac`` once per version of their sources.

The classes of an application's Java components are kept in the private cache directory
(:func:`acordcs.cachedir.private_dir`, under ``java/``), in a directory named by the digest of
every ``.java`` file of the ``java`` target's output (path and bytes) and of the ``javac``
used (its real path, size and time): a start with unchanged sources compiles nothing, a change compiles afresh into a new
directory (made beside it, then renamed: a reader sees a complete directory or none). Without a
private cache directory the classes go to a temporary one, removed when the process exits.

``javac`` compiles the user classes of the components hosted (``java/<package>/<C>.java``) and
what they use (``-sourcepath``: their generated bases, the Java API); nothing Java runs here. A
source that does not compile is a :class:`~.errors.JavaHostError` with javac's ``file:line``
and message, naming the component.
"""

from __future__ import annotations

import atexit
import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterable
from pathlib import Path

from acordcs.cachedir import private_dir
from acordcs.runtime.jvm.errors import JavaHostError

JDK_HINT = (
    "install a JDK 17 or later (Debian, Ubuntu: apt-get install openjdk-17-jdk-headless) so that "
    "javac and the JVM are found, or tag the component language=python"
)
COMPILE_TIMEOUT = 300.0  # seconds: javac of a few classes takes about one
_ERROR = re.compile(r"^(?P<file>.+?\.java):(?P<line>\d+): error: (?P<message>.*)$")


def source_digest(sources: Path, javac: str) -> str:
    """The digest naming the compiled classes of ``sources``: its ``.java`` files and javac."""
    digest = hashlib.sha256()
    digest.update(javac.encode() + b"\0")
    for path in sorted(sources.rglob("*.java")):
        digest.update(path.relative_to(sources).as_posix().encode() + b"\0")
        digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()[:32]


def javac_identity(javac: str) -> str:
    """Which javac: its real path, size and modification time (running ``javac -version`` would
    cost every start a JVM's start)."""
    real = os.path.realpath(javac)
    info = os.stat(real)
    return f"{real} {info.st_size} {info.st_mtime_ns}"


def compiled_classes(sources: Path, roots: Iterable[Path], components: str) -> Path:
    """The directory of the compiled classes of ``sources`` (a ``java`` target's output), the
    user classes ``roots`` and what they use: from the cache, else compiled now. ``components``
    names the components they are, for the errors."""
    javac = shutil.which("javac")
    if javac is None:
        raise JavaHostError(
            f"{components} tagged language=java: its classes must be compiled at start, and no "
            "javac is on PATH",
            hint=JDK_HINT,
        )
    version = javac_identity(javac)
    try:
        digest = source_digest(sources, version)
    except OSError as err:
        raise JavaHostError(
            f"{components} tagged language=java: cannot read its sources under {sources}: {err}",
            hint="rebuild the application (acordcs-gen build, with the java target)",
        ) from None
    cache = private_dir()
    if cache is None:
        parent = Path(tempfile.mkdtemp(prefix="acordcs-java-"))
        atexit.register(shutil.rmtree, parent, True)
    else:
        parent = Path(cache) / "java"
        parent.mkdir(mode=0o700, exist_ok=True)
    final = parent / digest
    if (final / ".complete").is_file():
        return final
    work = Path(tempfile.mkdtemp(prefix=f".{digest}.", dir=parent))
    try:
        _javac(javac, sources, list(roots), work, components)
        (work / ".complete").write_text(version + "\n", encoding="utf-8")
        try:
            os.rename(work, final)
        except OSError:  # another process made it meanwhile: theirs is as good
            if not (final / ".complete").is_file():
                raise
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return final


def _javac(javac: str, sources: Path, roots: list[Path], out: Path, components: str) -> None:
    command = [javac, "-encoding", "UTF-8", "-nowarn", "-implicit:class", "-proc:none",
               "-sourcepath", str(sources), "-d", str(out), *map(str, roots)]  # fmt: skip
    try:
        done = subprocess.run(
            command, capture_output=True, text=True, timeout=COMPILE_TIMEOUT, check=False
        )
    except subprocess.TimeoutExpired:
        raise JavaHostError(
            f"{components}: javac did not finish in {COMPILE_TIMEOUT:g} s", hint=JDK_HINT
        ) from None
    if done.returncode == 0:
        return
    said = (done.stderr or done.stdout).strip()
    errors = [found for line in said.splitlines() if (found := _ERROR.match(line))]
    if not errors:
        raise JavaHostError(f"{components}: javac failed: {said}", hint=JDK_HINT)
    first = errors[0]
    more = f"; javac found {len(errors) - 1} more error(s):\n{said}" if len(errors) > 1 else ""
    raise JavaHostError(
        f"{components}: its Java class does not compile: {first['message']}{more}",
        file=first["file"],
        line=int(first["line"]),
        hint="fix the Java source there (java/<package>/<Component>.java is yours), then start "
        "again",
    )
