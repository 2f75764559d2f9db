"""A container served as the launcher serves one (its endpoint, its management and observer
interfaces, one Pyro5 daemon, a token), in its own OS process, with no logging configured (as a
generated container module: Python's last-resort handler writes warnings to standard error).

Usage: ``python -m tests.support.managed_container TOKEN`` (from the repository's root) prints
``READY <port>`` once it serves, then runs until its standard input closes (so that it never
outlives the test that started it). The test sends its output to a file: the container's log.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

from acordcs.descriptor import to_xml
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management_server import manage
from tests.support.descriptors import application, component, container, prop, ref
from tests.support.toolchain import ROOT


def main() -> None:
    token = sys.argv[1]
    app = application(
        "Home",
        containers=(container("house", ref("component", "Heater")),),
        components=(component("Heater", properties=(prop("level", 0),)),),
    )
    run = assemble(app, clock=VirtualClock(), only=["house"], token=token)
    server = run.serve("house", host="127.0.0.1")
    manage(run, "house", server, to_xml(app), GivenClasses())
    print("READY", server.port, flush=True)
    sys.stdin.read()
    run.close()


@contextlib.contextmanager
def served_house(log: Path, token: str) -> Iterator[tuple[subprocess.Popen, int]]:
    """This module run as a child process (its output in ``log``), once it serves: (the process,
    its port). Resumed (SIGCONT) and ended when the block ends, killed if it does not end."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    env.pop("ACORDCS_TOKEN", None)
    with log.open("wb") as out:
        child = subprocess.Popen(
            [sys.executable, "-m", "tests.support.managed_container", token],
            cwd=ROOT,
            env=env,
            stdin=subprocess.PIPE,
            stdout=out,
            stderr=subprocess.STDOUT,
        )
    try:
        deadline = time.monotonic() + 60
        while not (found := re.search(r"READY (\d+)", log.read_text())):
            assert child.poll() is None, log.read_text()
            assert time.monotonic() < deadline, "the container did not start within 60 s"
            time.sleep(0.05)
        yield child, int(found.group(1))
    finally:
        child.send_signal(signal.SIGCONT)
        assert child.stdin is not None
        child.stdin.close()
        try:
            child.wait(20)
        except subprocess.TimeoutExpired:
            child.kill()
            child.wait(5)


if __name__ == "__main__":
    main()
