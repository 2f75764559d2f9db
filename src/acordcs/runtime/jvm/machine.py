"""The JVM of a process hosting Java components, through JPype's public API.

:func:`start_jvm` starts it once per process, only when a container hosts a component tagged
``language=java`` (an application of Python components never loads JPype): with ``-Xrs`` and
without JPype's interrupt handling, so that the launcher keeps its own SIGINT and SIGTERM
handling (Ctrl-C and ``bin/<Container>-stop`` stop the container as they stop a Python one),
and with JPype's ``convertStrings``: a Java ``String`` reaches Python as a ``str`` (one wrapper
fewer at each crossing; the host converts with ``str()`` all the same, in case another library
started the JVM without it).
A JVM cannot start twice in one process, nor take a classpath after its start: each directory of
compiled classes is loaded by a class loader of its own (:func:`java_class`), so two versions of
an application's classes (a replacement) can live side by side.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path
from typing import Any

from acordcs.javac import JDK_HINT
from acordcs.runtime.jvm.errors import JavaHostError

JPYPE_HINT = (
    "install JPype, the bridge acordcs hosts Java components through: pip install "
    "'acordcs[java]' (or pip install JPype1), or tag the component language=python"
)

_lock = threading.Lock()
_loaders: dict[str, Any] = {}
started_in: float | None = None
"""Seconds the JVM took to start in this process (None: not started by acordcs)."""


def start_jvm(components: str) -> Any:
    """The ``jpype`` module, the JVM started (once per process); ``components`` names what needs
    it, for the errors (:class:`JavaHostError`: no JPype, no JVM)."""
    global started_in
    try:
        import jpype
    except ImportError:
        raise JavaHostError(
            f"{components} tagged language=java: no JPype", hint=JPYPE_HINT
        ) from None
    with _lock:
        if jpype.isJVMStarted():
            return jpype
        try:
            path = jpype.getDefaultJVMPath()
        except jpype.JVMNotFoundException:
            raise JavaHostError(
                f"{components} tagged language=java: no Java virtual machine found (JAVA_HOME "
                "unset and no JVM in the usual places)",
                hint=JDK_HINT,
            ) from None
        began = time.perf_counter()
        try:
            jpype.startJVM(path, "-Xrs", interrupt=False, convertStrings=True)
        except (OSError, RuntimeError) as err:
            raise JavaHostError(
                f"{components} tagged language=java: the JVM at {path} did not start: {err}",
                hint=JDK_HINT,
            ) from None
        started_in = time.perf_counter() - began
    return jpype


def java_class(classes: Path, name: str, components: str) -> Any:
    """The Java class ``name`` (``package.Class``, or ``Outer$Inner``) of the compiled classes in
    ``classes``, loaded by that directory's class loader."""
    jpype = start_jvm(components)
    key = str(classes.resolve())
    with _lock:
        loader = _loaders.get(key)
        if loader is None:
            url = jpype.JClass("java.io.File")(key).toURI().toURL()
            urls = jpype.JArray(jpype.JClass("java.net.URL"))([url])
            loader = _loaders[key] = jpype.JClass("java.net.URLClassLoader")(urls)
    try:
        return jpype.JClass(name, loader=loader)
    except TypeError as err:  # JPype: class not found
        raise JavaHostError(
            f"{components}: no Java class {name} in the compiled classes ({err})",
            hint="rebuild the application (acordcs-gen build, with the java target)",
        ) from None
