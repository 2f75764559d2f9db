"""A watcher of a running container's observer interface in a process of its own, for tests that
run it on another network host (inside a network namespace):
``python -m tests.support.observer_peer HOST PORT CONTAINER [ELEMENT ...]`` (the token in
``$ACORDCS_TOKEN``).

It watches ``acordcs.observe.CONTAINER`` at ``HOST:PORT`` (:mod:`acordcs.runtime.live.observer`),
prints ``ready`` once the watch is made, then one JSON line per event of the ``ELEMENT``\\ s named
(a monitor's ``monitor.updated`` and ``monitor.stale``, a policy set's ``policy.fired``; all if
none is named) as the poll reply gives it, with ``wall``: the wall-clock time (``time.time()``) it
happened at, from the container's clock (the event's time and the reply's), so that a test can
place it against what it did. A poll that fails (the container gone) ends it, printing
``{"ended": "..."}``; it stops on SIGTERM or SIGKILL."""

from __future__ import annotations

import json
import os
import sys
import time

from acordcs.runtime.connectors.remote import RemoteConnector
from acordcs.runtime.errors import RuntimeFailure
from acordcs.runtime.live.observer import OBSERVE_OBJECT


def watch(host: str, port: int, container: str, elements: set[str]) -> None:
    uri = f"PYRO:{OBSERVE_OBJECT.format(container)}@{host}:{port}"
    connector = RemoteConnector(timeout=10, token=os.environ.get("ACORDCS_TOKEN") or None)
    where = f"the observer of {container}"
    reply = connector.request(uri, "watch", [], False, where=where)
    key, after = reply["watch"], reply["after"]
    print("ready", flush=True)
    try:
        while True:
            reply = connector.request(uri, "poll", key, after, 0.5, where=where)
            after = reply["after"]
            offset = time.time() - reply["time"]
            for event in reply["events"]:
                if elements and event["element"] not in elements:
                    continue
                print(json.dumps({**event, "wall": event["time"] + offset}), flush=True)
    except RuntimeFailure as err:
        print(json.dumps({"ended": str(err)[:300]}), flush=True)
    finally:
        connector.close()


if __name__ == "__main__":
    host, port, name, *names = sys.argv[1:]
    watch(host, int(port), name, set(names))
