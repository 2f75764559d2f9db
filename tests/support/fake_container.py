"""A stand-in for a generated container module, for the ``shell`` target's script tests: what a
start script runs (``python -m <package>.<Container> --exit-file PATH ...``) without the runtime.

It keeps the launcher's contract the scripts rely on: it prints ``<Container>: serving at <uri>``
once it serves, stops on TERM, and writes one line ``EXIT_CODE FAULTS`` to its ``--exit-file`` at
exit. Its behaviour is set by environment variables: ``FAKE_ARGS`` (a file receiving its
arguments, NUL-separated), ``FAKE_READY_AFTER`` (seconds before it serves; ``never``: it never
does), ``FAKE_IGNORE_TERM`` (``1``: TERM does not stop it), ``FAKE_FAIL`` (an exit code: it exits
with it at once, before serving, writing it with 0 faults), ``FAKE_EXIT_AFTER_SERVING`` (an exit
code: it says it serves, then exits with it at once, writing it with 0 faults). Without
``--exit-file`` it writes none (so that the tests can be run against scripts that do not pass
one, to see them fail)."""

from __future__ import annotations

from pathlib import Path

MODULE = """\
import os
import signal
import sys
import threading

CONTAINER = __spec__.name.rsplit(".", 1)[1]
args = sys.argv[1:]
if os.environ.get("FAKE_ARGS"):
    with open(os.environ["FAKE_ARGS"], "wb") as f:
        f.write(b"\\0".join(a.encode("utf-8", "surrogateescape") for a in args))
exit_file = args[args.index("--exit-file") + 1] if "--exit-file" in args else None


def leave(code, faults=0):
    if exit_file is not None:
        with open(exit_file + ".tmp", "w") as f:
            f.write(f"{code} {faults}\\n")
        os.replace(exit_file + ".tmp", exit_file)
    print(f"{CONTAINER}: stopped, faults: {faults}", flush=True)
    os._exit(code)


if os.environ.get("FAKE_FAIL"):
    print(f"{CONTAINER}: cannot start (FAKE_FAIL)", file=sys.stderr, flush=True)
    leave(int(os.environ["FAKE_FAIL"]))
stop = threading.Event()
if os.environ.get("FAKE_IGNORE_TERM") == "1":
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
else:
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
ready = os.environ.get("FAKE_READY_AFTER", "0")
if ready != "never":
    stop.wait(float(ready))
    print(f"{CONTAINER}: serving at PYRO:fake.{CONTAINER}@localhost:1", flush=True)
    if os.environ.get("FAKE_EXIT_AFTER_SERVING"):
        print(f"{CONTAINER}: fails at once (FAKE_EXIT_AFTER_SERVING)", file=sys.stderr, flush=True)
        leave(int(os.environ["FAKE_EXIT_AFTER_SERVING"]))
while not stop.wait(0.05):
    pass
leave(0)
"""


def install(out: Path, package: str, containers: tuple[str, ...]) -> None:
    """A fake ``package`` under ``out`` (where the scripts' ``PYTHONPATH`` points) whose module
    ``<C>`` for each of ``containers`` is the stand-in above."""
    root = out / package
    root.mkdir(parents=True, exist_ok=True)
    (root / "__init__.py").write_text("", encoding="utf-8")
    for name in containers:
        (root / f"{name}.py").write_text(MODULE, encoding="utf-8")
