"""The console of any running application: what ``acordcs-gen console APPDIR`` drives (a
:class:`~acordcs.console.web_app.Session`).

It reaches the application its scripts started (:class:`~acordcs.console.attaching.Application`:
``APPDIR/bin/env.sh``, the run directory, the token, each container's host and port), publishes
the page's model of it once (:func:`~acordcs.console.page_model.page_model`: the architecture,
the series, the policy sets, the forms), watches every container through its observer interface
(one :class:`~acordcs.console.attaching.Watcher` thread each) and publishes what they deliver as
it comes, on the hub's event channel (never waiting for a viewer: the hub drops a slow viewer's
oldest):

- ``monitor``: a monitor's new values (the page plots them on the container's clock);
- ``fired``: a policy set's firing: inputs read, each rule's degree (fuzzy) or the rules that
  fired (CLIPS, whose watch asks for them), outputs written;
- ``property``: a property changed (by whom: ``origin``);
- ``model.updated``: the plan line of a change an update applied;
- ``fault``: what a container recorded; ``down`` and ``up``: a container that stopped answering,
  and answers again;
- ``hold`` and ``released``: a component whose callers from other processes are held (the
  management interface's ``hold``: a console driving, a debugger), as the container's
  management side tells its watchers when a hold starts and ends (released, or expired).

and each container's snapshot on the latest channel ``snapshot:<container>``.

Its hands need the console's token (the link's fragment): ``call`` (an operation of a provided
port, through the container's endpoint as another container calls it), ``set`` (a component's
property, through the management interface: a change at run time), ``plan`` and ``apply``
(``acordcs-gen update`` itself, run with the model file given at start: the plan first, with
``--dry-run``, then the update on confirmation, in a child process with the console's
environment, so that the console has no second implementation of it).
"""

from __future__ import annotations

import hashlib
import os
import secrets
import shutil
import subprocess
import sys
import tempfile
import threading
from collections.abc import Callable, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

from acordcs.console import app_commands
from acordcs.console.attaching import Application, AttachError, Watcher
from acordcs.console.fanout import EVENT, ConsoleHub
from acordcs.console.page_model import page_model
from acordcs.console.panels import ConsolePanel, PanelContext, PanelSession, panels_for
from acordcs.console.viewer_messages import Command, read_object
from acordcs.console.web_app import ConsoleSite
from acordcs.plugins import PluginTable
from acordcs.runtime.errors import RuntimeFailure
from acordcs.runtime.live.observer import plain

SITE_NAME = "acordcs console"
UPDATE_SECONDS = 300.0
"""Seconds ``acordcs-gen update`` may take (a build, then each container's apply)."""
RUN_UPDATE = "import sys; from acordcs.cli import main; sys.exit(main(sys.argv[1:]))"
"""``acordcs-gen`` in a child process of this interpreter (the installed script may be elsewhere)."""
OUTPUT_KEPT = 20000
"""Characters of an update's output sent to the page (its end, when longer)."""


class LiveSession:
    """The console over the running application ``app``; ``token``: the console's (its link
    carries it); ``model``: the model file ``plan`` and ``apply`` build (None: no update from the
    page; needs ``app.app_dir``); ``panels``: what the application adds to the page
    (:mod:`.panels`), each given this application and token; ``admits``: who decides whether a
    viewer's token is the console's (default: compared with ``token``). :meth:`attached` attaches to the
    application built in a directory and started by its scripts."""

    def __init__(
        self,
        hub: ConsoleHub,
        token: str,
        app: Application,
        *,
        model: Path | None = None,
        panels: Sequence[ConsolePanel] = (),
        admits: Callable[[str], bool] | None = None,
    ) -> None:
        self.hub = hub
        self.token = token
        self.app = app
        self.model = model
        self.uploads: Path | None = None  # the directory of the models sent from the page
        self.admits = admits
        self.lock = threading.Lock()  # one update at a time
        self.answering: set[str] = set()  # the containers watched and answering (watchers' threads)
        self.page = page_model(self.app.descriptor)
        self.page["model"] = str(model) if model is not None else None
        hub.publish("application", self.page)
        self.panels = list(panels)
        context = PanelContext(hub, token, app)
        self.panel_sessions: dict[str, PanelSession] = {
            p.name: p.attach(context) for p in self.panels
        }
        watched: dict[str, list[str]] = {name: [] for name in self.app.places}
        for panel in self.panel_sessions.values():
            for container, calls in _optional(panel, "calls", dict)().items():
                watched[container].extend(c for c in calls if c not in watched[container])
        self.watchers = {
            name: Watcher(self.app, name, watched[name], self._deliver) for name in self.app.places
        }

    @classmethod
    def attached(
        cls,
        hub: ConsoleHub,
        token: str,
        app_dir: Path,
        *,
        model: Path | None = None,
        timeout: float = 5.0,
        panels: PluginTable[ConsolePanel] | None = None,
    ) -> LiveSession:
        """The console over the application built in ``app_dir`` and started by its scripts
        (AttachError when it cannot be found); ``timeout``: seconds a container may take;
        ``panels``: the table whose panels that apply to it go on its page."""
        app = Application.built_in(Path(app_dir), timeout)
        found = panels_for(app.descriptor, panels) if panels is not None else []
        return cls(hub, token, app, model=model, panels=found)

    # ---------------------------------------------------------------------------- the session
    def attach(self) -> str:
        """Watch every container (AttachError when one does not answer); what it attached to."""
        started: list[Watcher] = []
        try:
            for watcher in self.watchers.values():
                watcher.start_watching()
                started.append(watcher)
            for panel in self.panel_sessions.values():
                _optional(panel, "begin")()
        except AttachError:
            for watcher in started:
                watcher.stop()
            raise
        return f"{self.app.name}: {self.app.describe()}"

    def site(self) -> ConsoleSite:
        """The console's site: the library's page, subprotocol ``acordcs``, the commands of
        :mod:`.app_commands` over this application's operations and properties."""
        operations, properties = self.page["operations"], self.page["properties"]
        by_command = {c: p for p in self.panels if p.parse is not None for c in p.commands}

        def parse(text: str | bytes) -> Command:
            name = read_object(text).get("cmd")
            panel = by_command.get(name) if isinstance(name, str) else None
            if panel is not None and panel.parse is not None:
                return panel.parse(text)
            return app_commands.parse(text, operations, properties)

        return ConsoleSite(
            name=SITE_NAME,
            static=resources.files("acordcs.console") / "static",
            protocol="acordcs",
            parse=parse,
            binary_channels={k: v for p in self.panels for k, v in p.binary_channels.items()},
            paced={k: v for p in self.panels for k, v in p.paced.items()},
            panels={p.name: p.static for p in self.panels},
        )

    def describe(self) -> dict[str, Any]:
        return {"mode": self.app.mode, "application": self.app.name, "containers": list(self.app.places),
                "panels": [p.shown() for p in self.panels],
                "panel_state": {name: _described(panel)
                                for name, panel in self.panel_sessions.items()}}  # fmt: skip

    def handler(self, command: str) -> Callable[..., Any]:
        """What carries out ``command`` (as the site's parser read it): a panel's, or this
        session's own."""
        for panel in self.panels:
            if command in panel.commands:
                return getattr(self.panel_sessions[panel.name], command)
        return getattr(self, command)

    def authorize(self, token: str) -> bool:
        if self.admits is not None:
            return self.admits(token)
        return secrets.compare_digest(token.encode(), self.token.encode())

    def close(self) -> None:
        for panel in self.panel_sessions.values():
            _optional(panel, "close")()
        for watcher in self.watchers.values():
            watcher.stop()
        if self.uploads is not None:
            shutil.rmtree(self.uploads, ignore_errors=True)
        self.app.close()

    # ------------------------------------------------------------------------------ watching
    def _deliver(self, kind: str, container: str, data: Any) -> None:
        """What a watcher got, published (see the module docstring), and given to the panels;
        from its thread."""
        for panel in self.panel_sessions.values():
            _optional(panel, "deliver")(kind, container, data)
        publish = self.hub.publish
        if kind == "snapshot":
            publish(f"snapshot:{container}", data)
            if container not in self.answering:  # the first watch, or again after it was down
                self.answering.add(container)
                publish(EVENT, {"kind": "up", "container": container, "time": data.get("time")})
            return
        if kind == "down":
            self.answering.discard(container)
            publish(EVENT, {"kind": "down", "container": container, "why": str(data)[:500]})
            return
        for event in data.get("events", ()):
            shown = _shown(container, event)
            if shown is not None:
                publish(EVENT, shown)
        for fault in data.get("faults", ()):
            publish(EVENT, {"kind": "fault", "container": container, **fault})
        if data.get("dropped"):
            publish(EVENT, {"kind": "dropped", "container": container, "count": data["dropped"]})

    # ------------------------------------------------------------------------------- hands
    def call(self, component: str, port: str, operation: str, args: list[Any]) -> Any:
        """``component.operation(*args)`` through its provided ``port`` (an operation of the
        page model's, as :mod:`.app_commands` checked): its result, made plain for the page (a
        fault is raised: the server sends its text back)."""
        try:
            return plain(self.app.call(component, port, operation, *args))
        except RuntimeFailure as err:
            raise RuntimeError(err.message) from None

    def set(self, element: str, attribute: str, value: Any) -> Any:
        """Set property ``element.attribute`` through the management interface of the container
        hosting ``element`` (which types it by the model and refuses as it refuses updates)."""
        container = self.app.host_of.get(element.partition(".")[0])
        if container is None:
            raise ValueError(f"{element} is not a component of the model")
        try:
            return self.app.manage(container, "set_property", element, attribute, value)
        except RuntimeFailure as err:
            raise RuntimeError(err.message) from None

    def upload(self, name: str, data: bytes) -> dict[str, Any]:
        """A changed model sent from the page (``name``: its file's, ``data``: its bytes, as the
        server took them), written to a directory of the console's own (mode 700) and planned
        as :meth:`plan` plans: ``acordcs-gen update`` reads it (the project's hardened reader:
        its errors say file:line:col) and the page's next ``apply`` applies it."""
        if self.app.app_dir is None:
            raise RuntimeError(
                "the console has no application directory to update (a single-process run): "
                "update with acordcs-gen update"
            )
        with self.lock:
            if self.uploads is None:
                self.uploads = Path(tempfile.mkdtemp(prefix="acordcs-console-"))
            for old in self.uploads.iterdir():
                old.unlink()
            path = self.uploads / name
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            with os.fdopen(fd, "wb") as out:
                out.write(data)
            self.model = path
        self.hub.publish("model", {"model": name})
        return {**self.plan(), "model": name}

    def plan(self) -> dict[str, Any]:
        """What ``acordcs-gen update MODEL -o APPDIR --dry-run`` prints: the plan, nothing changed."""
        done = self._update("--dry-run")
        planned = hashlib.sha256(done["output"].encode()).hexdigest()
        return {**done, "plan": planned if done["code"] == 0 else None}

    def apply(self, plan: str) -> dict[str, Any]:
        """The update the plan ``plan`` (its digest, as :meth:`plan` gave it) showed, if planning
        again shows the same plan (the model or the application changed meanwhile: refused)."""
        with self.lock:
            again = self._update("--dry-run")
            if hashlib.sha256(again["output"].encode()).hexdigest() != plan:
                raise RuntimeError(
                    "the plan is not the one shown (the model file or the running application "
                    "changed meanwhile): plan again, and confirm the new plan"
                )
            return self._update()

    def _update(self, *options: str) -> dict[str, Any]:
        if self.model is None or self.app.app_dir is None:
            raise RuntimeError(
                "the console has no model to update from: send one from the page (Plan a "
                "changed model), or start the console with --model FILE"
            )
        argv = [sys.executable, "-c", RUN_UPDATE, "update", str(self.model),
                "-o", str(self.app.app_dir), *options]  # fmt: skip
        try:
            done = subprocess.run(
                argv, capture_output=True, text=True, timeout=UPDATE_SECONDS, check=False
            )
        except (OSError, subprocess.TimeoutExpired) as err:
            raise RuntimeError(f"acordcs-gen update did not run to its end: {err}") from None
        output = done.stdout + done.stderr
        if self.uploads is not None:  # a model from the page: its name, not our directory
            output = output.replace(f"{self.uploads}{os.sep}", "")
        output = output[-OUTPUT_KEPT:]
        return {"code": done.returncode, "output": output,
                "command": "acordcs-gen " + " ".join(argv[3:]).replace(
                    f"{self.uploads}{os.sep}" if self.uploads else "\0", "")}  # fmt: skip


def _described(panel: PanelSession) -> Any:
    """What a panel session tells a viewer first (its ``describe``, if it has one)."""
    return _optional(panel, "describe", lambda: None)()


def _optional(panel: PanelSession, method: str, default: Callable[[], Any] | None = None) -> Any:
    """A panel session's ``method``, or ``default`` (does nothing) when it has none: every
    method of :class:`~.panels.PanelSession` is optional."""
    return getattr(panel, method, None) or default or (lambda *args: None)


def _shown(container: str, event: dict[str, Any]) -> dict[str, Any] | None:
    """An observer event as the page shows it, or None (one it does not show)."""
    kind = event.get("kind")
    common = {"container": container, "time": event.get("time"), "element": event.get("element")}
    if kind == "monitor.updated":
        return {"kind": "monitor", **common, "values": event.get("values", {})}
    if kind == "policy.fired":
        firing = event.get("firing")
        return None if firing is None else {"kind": "fired", **common, **firing}
    if kind == "property.changed":
        return {"kind": "property", **common, "attribute": event.get("attribute"),
                "value": event.get("value"), "old": event.get("old"),
                "origin": event.get("origin")}  # fmt: skip
    if kind == "model.updated":
        return {"kind": "model.updated", **common, "line": str(event.get("value"))[:500]}
    data = event.get("data") or {}
    if kind == "monitor.stale":  # its last values kept (runtime/monitor.py), or fresh again
        return {"kind": "stale", **common, "stale": event.get("value") is True,
                "cause": str(data.get("cause", ""))[:500],
                "stale_for": data.get("stale_for")}  # fmt: skip
    if kind == "component.held":
        return {"kind": "hold", **common, "component": event.get("element"),
                "left": event.get("value"), "waiting": data.get("waiting")}  # fmt: skip
    if kind == "component.released":
        return {"kind": "released", **common, "component": event.get("element"),
                "why": event.get("value")}  # fmt: skip
    return None
