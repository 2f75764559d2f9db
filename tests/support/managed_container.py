"""A container served as the launcher serves one (its endpoint, its management and observer
interfaces, one Pyro5 daemon, a token), in its own OS process, with no logging configured (as a
generated container module: Python's last-resort handler writes warnings to standard error).

Usage: ``python -m tests.support.managed_container TOKEN`` (from the repository's root) prints
``READY <port>`` once it serves, then runs until its standard input closes (so that it never
outlives the test that started it). The test sends its output to a file: the container's log.
"""

from __future__ import annotations

import sys

from acordcs.descriptor import to_xml
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management import manage
from tests.support.descriptors import application, component, container, prop, ref


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


if __name__ == "__main__":
    main()
