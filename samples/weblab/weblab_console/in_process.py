"""The experiment run in this process (``make console``) as the console of any application reaches
a running one (:class:`acordcs.console.attaching.Application`'s ``observe``, ``manage``,
``call``), so that the console's own page and session (:mod:`acordcs.console.live_session`) show
it: each container of the running experiment gets an observer
(:class:`acordcs.runtime.live.observer.Observer`, the one a served container has) while the
run lasts, and the console's watches poll it directly instead of over Pyro5.

Between two runs no container runs: a watch then gets an empty snapshot and polls that wait;
the first poll in a new run watches its observer and answers with its snapshot, so that the
console sees every event of the run from its start. Calls and property changes run on
the experiment's thread (``run_on``, the session's), as everything touching it does; there are no
holds (no management interface) and no updates (no application directory).
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
        self.mode = "simulation"  # as the console's /status says it
        self.how_to_start = HOW_TO_START
        self.places = {c.name: c.name for c in descriptor.containers}
        self.host_of = {
            component: c.name for c in descriptor.containers for component in c.hosted("component")
        }
        self.lock = threading.Lock()
        self.changed = threading.Condition(self.lock)
        self.run = 0  # the run's number: 0 before the first
        self.observers: dict[str, Observer] = {}
        self.watches: dict[str, tuple[int, int, list[str]]] = {}  # container: run, watch, calls
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
        """The console's watch of ``container`` (one per container: its number is the
        container's place), carried from run to run: the first poll in a new run watches its
        observer and answers with its snapshot."""
        with self.lock:
            run, observer = self.run, self.observers.get(container)
        if method == "snapshot":
            return observer.snapshot() if observer is not None else _empty(container)
        if method == "watch":
            self.watches[container] = (-1, 0, list(args[0]))  # watched on the first poll
            return {"watch": list(self.places).index(container), "after": 0,
                    "snapshot": _empty(container)}  # fmt: skip
        watched, inner, calls = self.watches.get(container, (-1, 0, []))
        if method == "unwatch":
            self.watches.pop(container, None)
            if observer is not None and watched == run:
                observer.unwatch(inner)
            return True
        if observer is None:  # between runs: wait for one to start
            with self.changed:
                self.changed.wait_for(lambda: self.run != run, timeout=float(args[2]))
            return {"events": [], "after": 0, "dropped": 0, "more": False, "faults": [],
                    "time": 0.0}  # fmt: skip
        if watched != run:  # a new run: watch it, from its snapshot
            reply = observer.watch(calls, True)
            self.watches[container] = (run, reply["watch"], calls)
            return {"events": [], "after": reply["after"], "dropped": 0, "more": False,
                    "faults": [], "time": reply["snapshot"]["time"],
                    "snapshot": reply["snapshot"]}  # fmt: skip
        return observer.poll(inner, *args[1:])

    def manage(self, container: str, method: str, *args: Any) -> Any:
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
