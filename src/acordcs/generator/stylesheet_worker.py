"""The confined child processes that run the stylesheets a user did not mark trusted: Saxon in a
child of :mod:`acordcs.generator.sandbox`, without environment, reading only the stylesheet's own
directory and the descriptor's schema (Linux Landlock), kept from one build to the next of this
process; and the address space Saxon needs, checked before it starts (:mod:`.xslt` runs them)."""

from __future__ import annotations

import atexit
import contextlib
import sys
import tempfile
from importlib import resources

from acordcs.generator import sandbox
from acordcs.generator.errors import BuildError

DRIVER = "transform-target.xsl"
"""The stylesheet (in :mod:`acordcs.transforms`) that runs a target's stylesheet with
``fn:transform`` and returns its outputs' URIs and serializations (:mod:`.xslt` reads them)."""


def worker_for(
    readable: tuple[str, ...], name: str, stylesheet: str, origin: str
) -> StylesheetWorker:
    """The confined child process that runs target ``name``'s ``stylesheet`` (from ``origin``),
    reading only ``readable``: one per set of readable paths, kept for the next build of this
    process (a few at most)."""
    worker = _WORKERS.pop(readable, None)
    if worker is None or not worker.alive():
        check_address_space()
        confine = sandbox.abi() >= 1
        if not confine and origin != "acordcs":
            raise BuildError(
                f"target {name}: the stylesheet cannot be run confined here: this system "
                "has no Linux Landlock (Linux 5.13 or later, enabled), which keeps it to reading "
                "its own directory",
                file=stylesheet,
                hint="run it with --trust-stylesheet if you trust it: it then has your rights "
                "(every file you can read, the network, your environment variables)",
                exit_code=2,
            )
        worker = StylesheetWorker(readable, confine)
    _WORKERS[readable] = worker
    while len(_WORKERS) > _MAX_WORKERS:
        _WORKERS.pop(next(iter(_WORKERS))).close()
    return worker


_MAX_WORKERS = 3
_WORKERS: dict[tuple[str, ...], StylesheetWorker] = {}


class StylesheetWorker:
    """A child process of :mod:`acordcs.generator.sandbox` (what :func:`worker_for` keeps): Saxon, without environment, with
    ``allowedProtocols=file``, reading only ``readable`` (when ``confine``: Landlock)."""

    def __init__(self, readable: tuple[str, ...], confine: bool) -> None:
        import subprocess

        self.log = tempfile.TemporaryFile()  # noqa: SIM115  (what the child prints at start)
        self.descriptor = ""  # the digest of the descriptor the child holds
        self.process = subprocess.Popen(
            [sys.executable, "-I", "-S", sandbox.__file__],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self.log,
            env={},
            cwd="/",
        )
        setup = {
            "path": [p for p in sys.path if p],
            "driver": str(resources.files("acordcs.transforms") / DRIVER),
            "readable": list(readable),
            "confine": confine,
        }
        try:
            sandbox.send(self.process.stdin, setup)
            ready = sandbox.receive(self.process.stdout)
        except OSError:
            ready = None
        if not ready or not ready.get("ready"):
            said = (ready or {}).get("error") or self._log()
            self.close()
            raise engine_failed(said)

    def alive(self) -> bool:
        return self.process.poll() is None

    def run(self, request: dict, descriptor: bytes) -> dict:
        if request["descriptor"] != self.descriptor:
            request = {**request, "descriptor_text": descriptor.decode("utf-8")}
        try:
            sandbox.send(self.process.stdin, request)
            answer = sandbox.receive(self.process.stdout)
        except OSError:
            answer = None
        if answer is None:
            said = self._log()
            self.close()
            raise engine_failed(said or "its process ended while running the stylesheet")
        self.descriptor = request["descriptor"]
        return answer

    def _log(self) -> str:
        self.log.seek(0)
        return self.log.read().decode("utf-8", "replace").strip()

    def close(self) -> None:
        import subprocess

        for stream in (self.process.stdin, self.process.stdout):
            with contextlib.suppress(OSError):
                stream.close()  # type: ignore[union-attr]
        try:
            self.process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.log.close()


@atexit.register
def _close_workers() -> None:
    while _WORKERS:
        _WORKERS.popitem()[1].close()


def engine_failed(said: str) -> BuildError:
    """The XSLT engine could not start or ended (what it said: ``said``)."""
    if "graal_create_isolate" in said or "IsolateThread" in said:
        return address_space_error()
    return BuildError(
        f"the XSLT engine (Saxon) failed: {said or 'it said nothing'}",
        hint="nothing was written; build again, and report it if it happens again",
        exit_code=2,
    )


# Saxon is a GraalVM native image: its isolate reserves 32 GiB of address space when it starts,
# and a process limited below that (ulimit -v) is ended by it with "graal_create_isolate error".
_ADDRESS_SPACE = 34 * 1024**3  # bytes: the reservation and the interpreter beside it


def check_address_space() -> None:
    """A BuildError, before Saxon starts, when ``ulimit -v`` leaves it too little address space."""
    try:
        import resource
    except ImportError:  # not on a POSIX system: no such limit
        return
    soft, _hard = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY and soft < _ADDRESS_SPACE:
        raise address_space_error(soft)


def address_space_error(limit: int | None = None) -> BuildError:
    now = f" (it is {limit // 1024} KiB)" if limit is not None else ""
    return BuildError(
        "the XSLT engine (Saxon, a GraalVM native image) could not reserve its address space: it "
        "reserves 32 GiB of virtual memory when it starts (not memory it uses), and this process's "
        f"address-space limit, ulimit -v{now}, is below that",
        hint=f"raise the limit: ulimit -v unlimited, or at least ulimit -v {_ADDRESS_SPACE // 1024} "
        "(KiB), then build again; nothing was written",
        exit_code=2,
    )
