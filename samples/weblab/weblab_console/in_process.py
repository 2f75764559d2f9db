"""The experiment run in this process (``make console``) as the console of any application reaches
a running one (:class:`acordcs.console.attaching.Application`'s ``observe``, ``manage``,
``call``), so that the console's own page and session (:mod:`acordcs.console.live_session`) show
it: each container of the running experiment gets an observer
(:class:`acordcs.runtime.live.observer.Observer`, the one a served container has) while the
run lasts, and the console's watches poll it directly instead of over Pyro5.

Between two runs no container runs: a watch then gets an empty snapshot and polls that wait;
a watch of a run that ended is told so (a :class:`RuntimeFailure`), and watches again: the
console shows the container stopping and answering again. Calls and property changes run on
the experiment's thread (``run_on``, the session's), as everything touching it does; there are no
holds and no updates (no application directory).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from weblab_sim import experiment

from acordcs.descriptor import from_xml
from acordcs.runtime.errors import RuntimeFailure
from acordcs.runtime.live.observer import Observer
from acordcs.runtime.live.property_setting import model_property, typed

WATCHES_PER_RUN = 1_000_000
"""A watch's number is its run's times this, plus the observer's own."""

HOW_TO_START = "press Start in the WebLab panel (or start the console with --start PROFILE)"


def weblab_descriptor() -> Any:
    """The descriptor the generated WebLab application runs (``app/weblab_app/descriptor.xml``)."""
    path = Path(experiment.APP_DIR) / "weblab_app" / "descriptor.xml"
    return from_xml(path.read_bytes(), file=str(path))


class InProcess:
    """The experiment's containers, while one runs (:meth:`running`, :meth:`ended`)."""

    def __init__(self, descriptor: Any) -> None:
        self.descriptor = descriptor
        self.name = descriptor.name
        self.app_dir = None
        self.how_to_start = HOW_TO_START
        self.places = {c.name: c.name for c in descriptor.containers}
        self.host_of = {
            component: c.name for c in descriptor.containers for component in c.hosted("component")
        }
        self.lock = threading.Lock()
        self.changed = threading.Condition(self.lock)
        self.run = 0  # the run's number: 0 before the first
        self.observers: dict[str, Observer] = {}
        self.containers: Mapping[str, Any] = {}
        self.run_on: Callable[[Callable[[], Any]], Any] | None = None

    def running(
        self, containers: Mapping[str, Any], run_on: Callable[[Callable[[], Any]], Any]
    ) -> None:
        """A run started with ``containers``; ``run_on(fn)`` runs ``fn`` on its thread."""
        lab = tuple(experiment.POLICY_SETS)
        observers = {
            name: Observer(c, (lambda: lab) if name == "WebLabSide" else tuple)
            for name, c in containers.items()
        }
        with self.changed:
            self.run += 1
            self.observers, self.containers, self.run_on = observers, dict(containers), run_on
            self.changed.notify_all()

    def ended(self) -> None:
        with self.changed:
            observers, self.observers, self.containers, self.run_on = self.observers, {}, {}, None
            self.run += 1
            self.changed.notify_all()
        for observer in observers.values():
            observer.close()

    # ------------------------------------------------------------ as attaching.Application
    def observe(self, container: str, method: str, *args: Any) -> Any:
        with self.lock:
            run, observer = self.run, self.observers.get(container)
        if method == "watch":
            if observer is None:
                return {"watch": run * WATCHES_PER_RUN, "after": 0, "snapshot": _empty(container)}
            reply = observer.watch(*args)
            return {**reply, "watch": run * WATCHES_PER_RUN + reply["watch"]}
        if method == "snapshot":
            return observer.snapshot() if observer is not None else _empty(container)
        watch = int(args[0])
        if watch // WATCHES_PER_RUN != run:
            raise RuntimeFailure(
                "the experiment it watched ended: watching the next one", where=container
            )
        if method == "unwatch":
            return observer.unwatch(watch % WATCHES_PER_RUN) if observer is not None else True
        if observer is None:  # between runs: wait for one to start
            with self.changed:
                self.changed.wait_for(lambda: self.run != run, timeout=float(args[2]))
            return {"events": [], "after": 0, "dropped": 0, "more": False, "faults": [],
                    "time": 0.0}  # fmt: skip
        return observer.poll(watch % WATCHES_PER_RUN, *args[1:])

    def manage(self, container: str, method: str, *args: Any) -> Any:
        if method == "status":
            return {"holds": []}
        if method != "set_property":
            raise RuntimeFailure(f"the experiment in this process has no {method}", where=container)
        element, attribute, value = args
        prop = model_property(self.descriptor, container, element, attribute)
        new = typed(prop, value)

        def change() -> dict[str, Any]:
            box = self.containers[container]
            old = box.get_property(element, attribute)
            box.set_property(element, attribute, new)
            return {"element": element, "attribute": attribute, "value": new, "old": old}

        return self._on_run(container, change)

    def call(self, component: str, port: str, operation: str, *args: Any) -> Any:
        container = self.host_of[component]
        return self._on_run(
            container,
            lambda: self.containers[container].find(component).port(port).call(operation, *args),
        )

    def describe(self) -> str:
        return "the experiment in this process, on a simulated clock"

    def close(self) -> None:
        self.ended()

    def _on_run(self, container: str, fn: Callable[[], Any]) -> Any:
        with self.lock:
            run_on = self.run_on
        if run_on is None:
            raise RuntimeFailure(f"no experiment runs: {HOW_TO_START}", where=container)
        return run_on(fn)


def _empty(container: str) -> dict[str, Any]:
    """A container's snapshot between two runs: nothing runs."""
    return {"container": container, "time": 0.0, "seed": 0, "elements": {}, "policy_sets": {},
            "faults": 0}  # fmt: skip
