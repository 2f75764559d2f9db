"""Running stylesheets confined: a child process that reads only the paths it is given, reaches
no network and sees no environment variable (how :mod:`acordcs.generator.xslt` runs every
stylesheet but those the user trusts, ``--trust-stylesheet``).

The child (:func:`main`, this file run by path: it imports nothing of acordcs) starts with an
empty environment and the working directory ``/``, clears what Python put in its environment,
creates Saxon's processor with ``allowedProtocols=file`` (Saxon refuses every URI but ``file:``:
no ``http:``, ``https:``, ``ftp:``, ``jar:``), compiles the driver stylesheet, then restricts
itself with Linux Landlock (:func:`restrict`) to reading the paths given, for good, before it
reads a request: the stylesheet's own directory and the descriptor's schema. Requests and answers
are JSON documents over its standard input and output, each preceded by its length.

Landlock (Linux 5.13 and later) lets an unprivileged process restrict itself: once
:func:`restrict` returned, the process and its children can read only the files and directories
under the paths given (read only: no write, create, remove, rename, truncate, execute anywhere),
and, from ABI 4 (Linux 6.7), neither connect nor bind a TCP socket; from ABI 6 it cannot reach
abstract UNIX sockets or signal processes outside it. File descriptors already open stay usable.
A symbolic link under an allowed path that points out of it is refused: Landlock checks the file
reached, not the name. The calls are made through :mod:`ctypes` (the system calls 444 to 446, the
same numbers on every architecture Linux gives them to).
"""

from __future__ import annotations

import ctypes
import json
import os
import struct
import sys
from collections.abc import Iterable

_CREATE_RULESET, _ADD_RULE, _RESTRICT_SELF = 444, 445, 446
_VERSION = 1 << 0  # landlock_create_ruleset's flag: return the ABI version
_PATH_BENEATH = 1
_PR_SET_NO_NEW_PRIVS = 38

_READ_FILE, _READ_DIR = 1 << 2, 1 << 3
_FS_V1 = (1 << 13) - 1  # execute, write, read file and dir, remove and make every kind of file
_FS_LATER = {2: 1 << 13, 3: 1 << 14, 5: 1 << 15}  # refer, truncate, ioctl on devices
_NET_TCP = (1 << 0) | (1 << 1)  # bind and connect (ABI 4)
_SCOPES = (1 << 0) | (1 << 1)  # abstract UNIX sockets, signals (ABI 6)


class LandlockError(OSError):
    """Landlock could not be applied (what failed, in words)."""


def _libc():
    libc = ctypes.CDLL(None, use_errno=True)
    libc.syscall.restype = ctypes.c_long
    return libc


def abi() -> int:
    """The Landlock ABI version the kernel offers, 0 when it offers none (not Linux, a kernel
    before 5.13, Landlock disabled at boot, or the system call filtered)."""
    if os.uname().sysname != "Linux":
        return 0
    try:
        version = _libc().syscall(
            _CREATE_RULESET, None, ctypes.c_size_t(0), ctypes.c_uint32(_VERSION)
        )
    except (OSError, AttributeError):
        return 0
    return max(int(version), 0)


def restrict(readable: Iterable[str]) -> int:
    """Restrict this process for good: it may read the files and directories under ``readable``
    (each a directory or a file) and nothing else; no TCP where the kernel can say so. Returns the
    ABI used; :class:`LandlockError` when Landlock is not there or a call fails (then nothing was
    restricted)."""
    version = abi()
    if version < 1:
        raise LandlockError("Landlock is not available on this system")
    libc = _libc()
    fs = _FS_V1
    for since, bits in _FS_LATER.items():
        if version >= since:
            fs |= bits
    net = _NET_TCP if version >= 4 else 0
    scoped = _SCOPES if version >= 6 else 0
    size = 24 if version >= 6 else 16 if version >= 4 else 8
    attr = ctypes.create_string_buffer(struct.pack("=QQQ", fs, net, scoped)[:size], size)
    ruleset = libc.syscall(_CREATE_RULESET, attr, ctypes.c_size_t(size), ctypes.c_uint32(0))
    if ruleset < 0:
        raise LandlockError(f"landlock_create_ruleset: {os.strerror(ctypes.get_errno())}")
    try:
        for path in readable:
            try:
                handle = os.open(path, os.O_PATH | os.O_CLOEXEC)
            except OSError as err:
                raise LandlockError(f"{path}: {err.strerror}") from None
            try:
                rights = _READ_FILE | (_READ_DIR if os.path.isdir(path) else 0)
                rule = ctypes.create_string_buffer(struct.pack("=Qi", rights, handle), 12)
                done = libc.syscall(
                    _ADD_RULE, ctypes.c_int(ruleset), ctypes.c_int(_PATH_BENEATH), rule,
                    ctypes.c_uint32(0),
                )  # fmt: skip
                if done != 0:
                    raise LandlockError(
                        f"landlock_add_rule {path}: {os.strerror(ctypes.get_errno())}"
                    )
            finally:
                os.close(handle)
        if libc.prctl(_PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
            raise LandlockError(f"prctl(PR_SET_NO_NEW_PRIVS): {os.strerror(ctypes.get_errno())}")
        if libc.syscall(_RESTRICT_SELF, ctypes.c_int(ruleset), ctypes.c_uint32(0)) != 0:
            raise LandlockError(f"landlock_restrict_self: {os.strerror(ctypes.get_errno())}")
    finally:
        os.close(ruleset)
    return version


# The child: this file run by path (``python -I -S sandbox.py``), importing nothing of acordcs.

ALLOWED_PROTOCOLS = "http://saxon.sf.net/feature/allowedProtocols"
_FRAME = struct.Struct(">Q")


def send(stream, message: dict) -> None:
    """``message`` as JSON, preceded by its length in bytes (8 bytes, big-endian)."""
    data = json.dumps(message, ensure_ascii=False).encode("utf-8", "surrogatepass")
    stream.write(_FRAME.pack(len(data)) + data)
    stream.flush()


def receive(stream) -> dict | None:
    """The next message :func:`send` wrote on ``stream``; None at its end."""
    head = stream.read(_FRAME.size)
    if len(head) < _FRAME.size:
        return None
    (length,) = _FRAME.unpack(head)
    data = stream.read(length)
    if len(data) < length:
        return None
    return json.loads(data.decode("utf-8", "surrogatepass"))


def messages(driver) -> list[str]:
    """The ``xsl:message`` texts the driver's last transformation collected."""
    try:
        found = driver.get_xsl_messages()
    except Exception:  # saxonche gives nothing when no message was sent
        return []
    if found is None:
        return []
    return [str(getattr(item, "string_value", item)).strip() for item in found]


def transform(processor, driver, request: dict, documents: dict) -> dict:
    """Run the driver over the request's descriptor (parsed once: kept in ``documents`` by its
    digest) with the request's stylesheet and parameters: ``framed`` (the driver's result, None
    on failure), ``error`` (Saxon's exception, or None) and ``messages``."""
    from saxonche import PySaxonApiError

    framed: str | None = None
    error: str | None = None
    driver.clear_parameters()
    driver.clear_xsl_messages()
    try:
        digest = request["descriptor"]
        if "descriptor_text" in request:
            documents.clear()
            documents[digest] = processor.parse_xml(xml_text=request["descriptor_text"])
        driver.set_parameter("stylesheet", processor.make_string_value(request["stylesheet"]))
        driver.set_parameter("base", processor.make_string_value(request["base"]))
        values = {k: processor.make_string_value(v) for k, v in request["parameters"].items()}
        driver.set_parameter("parameters", processor.make_map2(values))
        result = driver.transform_to_value(xdm_node=documents[digest])
        framed = result.head.string_value if result is not None and result.size else ""
    except PySaxonApiError as err:
        error = str(err).strip() or type(err).__name__
    return {"framed": framed, "error": error, "messages": messages(driver)}


def start(driver_path: str, allowed_protocols: str | None):
    """Saxon's processor (``allowed_protocols``: Saxon's ``allowedProtocols``, None for all) and
    the compiled driver stylesheet."""
    from saxonche import PySaxonProcessor

    processor = PySaxonProcessor(license=False)
    if allowed_protocols is not None:
        processor.set_configuration_property(ALLOWED_PROTOCOLS, allowed_protocols)
    driver = processor.new_xslt30_processor().compile_stylesheet(stylesheet_file=driver_path)
    driver.set_result_as_raw_value(True)  # the map itself, not a serialization of it
    driver.set_save_xsl_message(True)
    return processor, driver


def _drained(sink) -> str:
    sink.flush()
    sink.seek(0)
    text = sink.read().decode("utf-8", "replace").strip()
    sink.seek(0)
    sink.truncate()
    return text


def main() -> int:
    """The child's loop: set up from the first message, say ready, answer each request."""
    import tempfile

    for name in list(os.environ):  # unsetenv: Saxon reads the process's C environment
        del os.environ[name]
    channel_in = os.fdopen(os.dup(0), "rb")
    channel_out = os.fdopen(os.dup(1), "wb")
    null = os.open(os.devnull, os.O_RDWR)
    os.dup2(null, 0)
    os.dup2(null, 1)  # nothing but the answers on the channel
    setup = receive(channel_in)
    if setup is None:
        return 1
    sys.path[:] = setup["path"]
    sink = tempfile.TemporaryFile()  # noqa: SIM115  (what Saxon prints, per request)
    try:
        processor, driver = start(setup["driver"], "file")
        import saxonche  # noqa: F401  (every module it needs, loaded before the restriction)

        version = restrict(setup["readable"]) if setup["confine"] else 0
    except Exception as err:
        send(channel_out, {"ready": False, "error": f"{type(err).__name__}: {err}"})
        return 1
    os.dup2(sink.fileno(), 2)
    send(channel_out, {"ready": True, "abi": version})
    documents: dict = {}
    while (request := receive(channel_in)) is not None:
        try:
            answer = transform(processor, driver, request, documents)
        except Exception as err:  # a fault of this loop, not of the stylesheet
            answer = {"framed": None, "error": f"{type(err).__name__}: {err}", "messages": []}
        answer["said"] = _drained(sink)
        send(channel_out, answer)
    return 0


if __name__ == "__main__":
    sys.exit(main())
