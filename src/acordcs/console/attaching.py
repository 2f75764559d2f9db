"""A running application as an attached console reaches it: where each container serves, found as
its generated scripts find it (:func:`acordcs.runtime.live.app_settings.settings` sources ``bin/env.sh``: the run
directory, the application's token, each container's host and port), its descriptor (which
container hosts which component, and all the rest the console shows), and the calls the console
makes, each presenting the application's token: an operation through a component's provided port
(the container's endpoint, as another container calls it), the observer interface (``watch``,
``poll``: :mod:`acordcs.runtime.live.observer`) and the management interface (``status``,
``hold``, ``release``...: :mod:`acordcs.runtime.live.management`).

:class:`Watcher` is one container's watch: a thread that polls its observer and hands what it
gets to the console's loop, watching again (with a new snapshot) after the container was
unreachable or when it says events were missed.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from acordcs.descriptor import DescriptorError, from_xml
from acordcs.runtime.connectors.remote import RemoteConnector, bytes_back, container_uri
from acordcs.runtime.errors import RuntimeFailure
from acordcs.runtime.live.app_settings import NotFound, settings
from acordcs.runtime.live.management_server import MANAGE_OBJECT
from acordcs.runtime.live.observer import OBSERVE_OBJECT

if TYPE_CHECKING:
    from acordcs.descriptor import Application as AppDescriptor

POLL_WAIT = 1.0  # seconds a poll waits for something new
RETRY = 2.0  # seconds between attempts to reach a container that did not answer


HOW_TO_START = (
    "start the application first (its bin/start-all, with the same ACORDCS_RUN_DIR and ports "
    "as the console's environment)"
)


class AttachError(RuntimeError):
    """The application cannot be reached; ``str()`` says why and what to do."""


@dataclass(frozen=True)
class Place:
    """Where container ``name`` serves, and the URIs of its three Pyro5 objects."""

    name: str
    host: str
    port: int

    @property
    def endpoint(self) -> str:
        return container_uri(self.name, self.host, self.port)

    @property
    def observer(self) -> str:
        return f"PYRO:{OBSERVE_OBJECT.format(self.name)}@{self.host}:{self.port}"

    @property
    def management(self) -> str:
        return f"PYRO:{MANAGE_OBJECT.format(self.name)}@{self.host}:{self.port}"


class Application:
    """An application's running containers as a console reaches them: ``descriptor``, what it
    runs; ``places``, where each container serves; ``token``, the application's (empty: none);
    ``timeout``: seconds a call may take; ``how_to_start``: what a container that does not answer
    is told to do; ``app_dir``: the directory it was built in (None: not known, as for a
    single process that serves its own console); ``mode``: how it runs, as the console's
    ``/status`` says it. :meth:`built_in` finds them as the scripts do."""

    def __init__(
        self,
        descriptor: AppDescriptor,
        places: Mapping[str, Place],
        token: str,
        timeout: float,
        how_to_start: str = HOW_TO_START,
        app_dir: Path | None = None,
        mode: str = "attached",
    ) -> None:
        self.descriptor = descriptor
        self.mode = mode
        self.places = dict(places)
        self.token = token
        self.how_to_start = how_to_start
        self.app_dir = app_dir
        self.name = descriptor.name
        self.host_of = {
            component: c.name for c in descriptor.containers for component in c.hosted("component")
        }
        self.connector = RemoteConnector(timeout=timeout, token=token or None)

    @classmethod
    def built_in(
        cls, app_dir: Path, timeout: float, how_to_start: str = HOW_TO_START
    ) -> Application:
        """The application built in ``app_dir`` as its scripts run it (see the module
        docstring), or AttachError saying why not."""
        try:
            found = settings(app_dir)
        except NotFound as err:
            raise AttachError(f"{err}" + (f" ({err.hint})" if err.hint else "")) from None
        path = app_dir / found.package / "descriptor.xml"
        try:
            descriptor = from_xml(path.read_bytes(), file=str(path))
        except (OSError, DescriptorError) as err:
            raise AttachError(f"{path}: {err}: build the application first") from None
        places = {}
        for name, (host, port) in found.containers.items():
            if not port.isdigit():
                raise AttachError(f"container {name}: its port is {port!r}, not a number")
            places[name] = Place(name, host, int(port))
        return cls(descriptor, places, found.token, timeout, how_to_start, Path(app_dir))

    def place_of(self, component: str) -> Place:
        return self.places[self.host_of[component]]

    def call(self, component: str, port: str, operation: str, *args: Any) -> Any:
        """``component.operation(*args)`` through its provided ``port``, as another container
        calls it (its interceptors and monitors see the call)."""
        where = self.place_of(component)
        reply = self.connector.request(
            where.endpoint,
            "call",
            component,
            port,
            operation,
            list(args),
            {},
            where=f"{component}.{operation}() in {where.name} at {where.host}:{where.port}",
            what=f"{operation}()",
        )
        return bytes_back(reply)

    def observe(self, container: str, method: str, *args: Any) -> Any:
        where = self.places[container]
        return self.connector.request(
            where.observer, method, *args, where=f"the observer of {container}", what=method
        )

    def manage(self, container: str, method: str, *args: Any) -> Any:
        where = self.places[container]
        return self.connector.request(
            where.management, method, *args, where=f"the management of {container}", what=method
        )

    def describe(self) -> str:
        return ", ".join(f"{p.name} at {p.host}:{p.port}" for p in self.places.values())

    def close(self) -> None:
        self.connector.close()


class Watcher(threading.Thread):
    """Container ``container``'s watch (see the module docstring): ``deliver(kind, container,
    data)`` gets ``("snapshot", c, snapshot)``, ``("events", c, poll reply)`` and ``("down", c,
    why)`` (once, each time it stops answering), from this thread."""

    def __init__(
        self,
        app: Application,
        container: str,
        calls: list[str],
        deliver: Callable[[str, str, Any], None],
    ) -> None:
        super().__init__(name=f"acordcs-console-watch-{container}", daemon=True)
        self.app = app
        self.container = container
        self.calls = calls
        self.deliver = deliver
        self.stopping = threading.Event()
        self.watch: int | None = None
        self.reachable = False

    def start_watching(self) -> None:
        """Watch (in the caller's thread: AttachError when the container does not answer), then
        poll in this thread."""
        try:
            self._watch()
        except RuntimeFailure as err:
            raise AttachError(
                f"container {self.container} does not answer: {err.message}: "
                f"{self.app.how_to_start}"
            ) from None
        self.start()

    def _watch(self) -> None:
        reply = self.app.observe(self.container, "watch", self.calls, True)
        self.watch, self.after, self.reachable = reply["watch"], reply["after"], True
        self.deliver("snapshot", self.container, reply["snapshot"])

    def run(self) -> None:
        while not self.stopping.is_set():
            try:
                if not self.reachable:
                    self._watch()
                reply = self.app.observe(self.container, "poll", self.watch, self.after, POLL_WAIT)
                if reply["dropped"]:  # fell behind the container's ring: start again from now
                    reply["snapshot"] = self.app.observe(self.container, "snapshot")
            except RuntimeFailure as err:
                if self.reachable:
                    self.reachable = False
                    self.deliver("down", self.container, err.message)
                self.stopping.wait(RETRY)
                continue
            self.after = reply["after"]
            self.deliver("events", self.container, reply)
            if "snapshot" in reply:
                self.deliver("snapshot", self.container, reply["snapshot"])

    def stop(self) -> None:
        self.stopping.set()
        if self.ident is not None:  # started
            self.join(POLL_WAIT + 5.0)
        if self.watch is not None and self.reachable:
            with contextlib.suppress(RuntimeFailure):  # gone meanwhile: its watch expires there
                self.app.observe(self.container, "unwatch", self.watch)
