"""The state of the components the model tags ``persistent``, kept in the application's run
directory across a stop or a crash of their container.

Each such component has one file there, ``<Component>.state.json``: its properties (those the
model declares) and its state fields (``state_fields``), as :meth:`CtxComponent.save_state` gives
them, as strict JSON. A container writes it (:class:`Persistence`) a moment after a property of the
component changed (at most one write per :data:`WRITE_INTERVAL` seconds: changes in between are
coalesced into the next write) and when it stops; each write replaces the file whole (a temporary
file beside it, fsync, rename, fsync of the directory), so that a crash leaves the old file or the
new one, never a part. At start it reads the file (:class:`StateStore`) and the component takes
that state before its ``on_start``.

The file is hostile input: read without following a link or waiting on a FIFO, at most
:data:`STATE_LIMIT` bytes, strict JSON (no NaN, no duplicate key), every property value typed by
the model's kind for it; signed with the application's token (HMAC-SHA256 over the canonical JSON
of what it says) when there is one, so that a file someone else wrote is refused. A file refused is
moved aside (``<Component>.state.json.refused-<time>``: kept, never deleted), said on standard
error naming the file, the component and why, and the component starts from the model's initial
values. A property the file holds that the model no longer declares is ignored.
"""

from __future__ import annotations

import contextlib
import hashlib
import hmac
import json
import os
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from acordcs.bounded_read import Unreadable, read_bounded
from acordcs.runtime import events as ev
from acordcs.runtime.errors import ConfigurationError, RuntimeFailure
from acordcs.runtime.live.property_setting import typed

if TYPE_CHECKING:
    from acordcs.descriptor.application import Component as ComponentDescription
    from acordcs.descriptor.application import Property
    from acordcs.runtime.component import CtxComponent
    from acordcs.runtime.container import Container
    from acordcs.runtime.events import Event

FORMAT = "acordcs-state/1"
"""What a state file says it is (its ``format``)."""

STATE_LIMIT = 1024 * 1024
"""The largest state file read or written (1 MiB): a larger one is refused, a larger state not
written (said once)."""

WRITE_INTERVAL = 0.25
"""Seconds between two writes of one container's state files, at least: a property that changed
is on disk within about this long, and a burst of changes is one write."""

SIGNATURE = "hmac-sha256"

Say = Callable[[str], None]


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


class StateRefused(ValueError):
    """A state file that is not taken: why, in words."""


def state_file(directory: Path, component: str) -> Path:
    """Where the state of ``component`` is kept in the run directory ``directory``."""
    return directory / f"{component}.state.json"


def _canonical(value: object) -> bytes:
    return json.dumps(
        value, sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False
    ).encode("ascii")


def _no_constant(name: str) -> object:
    raise StateRefused(f"not strict JSON: {name} is no JSON number")


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise StateRefused(f"not strict JSON: the key {key!r:.60} appears twice in one object")
        out[key] = value
    return out


class StateStore:
    """The state file of one persistent component ``component`` (its description: the properties
    and their kinds) of application ``application``, in the run directory ``directory``; signed
    and checked with ``token`` when given. Warnings go to ``say``."""

    def __init__(
        self,
        directory: Path,
        application: str,
        component: ComponentDescription,
        *,
        token: str | None = None,
        say: Say = _stderr,
        limit: int = STATE_LIMIT,
    ) -> None:
        self.path = state_file(directory, component.name)
        self.application = application
        self.component = component.name
        self.declared: dict[str, Property] = {p.name: p for p in component.properties}
        self.key = token.encode("utf-8") if token else None
        self.say = say
        self.limit = limit
        self.writable = True  # False once a file that could not be moved aside is there
        self._said: set[str] = set()  # what a write left out, said once each

    # ------------------------------------------------------------------------------ reading
    def load(self) -> dict[str, Any] | None:
        """The state the file holds (``{"properties": ..., "fields": ...}``, the properties typed
        by the model), or None: no file, or a file refused (said, and moved aside). The
        temporary files a write killed half-way left (never the state: that is renamed whole)
        are removed."""
        for left in self.path.parent.glob(f".{self.path.name}.*.tmp"):
            with contextlib.suppress(OSError):
                if left.is_file() and not left.is_symlink():
                    left.unlink()
        try:
            data = read_bounded(self.path, self.limit)
        except FileNotFoundError:
            return None
        except Unreadable as err:
            return self._refuse(f"it is {err.what}")
        except OSError as err:
            return self._refuse(f"it cannot be read: {err.strerror or err}")
        try:
            state, ignored = self._checked(data)
        except StateRefused as err:
            return self._refuse(str(err))
        fields = state.get("fields", {})
        said = f"{len(state['properties'])} properties, {len(fields)} state fields"
        if ignored:
            said += f"; ignored, no longer in the model: {', '.join(sorted(ignored))}"
        self.say(f"{self.component}: state restored from {self.path} ({said})")
        return state

    def _checked(self, data: bytes) -> tuple[dict[str, Any], list[str]]:
        try:
            text = data.decode("utf-8")
            doc = json.loads(text, parse_constant=_no_constant, object_pairs_hook=_unique_keys)
        except UnicodeDecodeError:
            raise StateRefused("it is not UTF-8 text") from None
        except json.JSONDecodeError as err:
            raise StateRefused(
                f"it is not JSON ({err.msg} at line {err.lineno}, column {err.colno})"
            ) from None
        except RecursionError:
            raise StateRefused("it nests too deeply") from None
        if not isinstance(doc, dict):
            raise StateRefused("it is not a JSON object")
        expected = {"format", "application", "component", "state", SIGNATURE}
        unknown = sorted(set(doc) - expected)
        if unknown:
            raise StateRefused(f"it has keys a state file does not: {', '.join(unknown)[:200]}")
        if doc.get("format") != FORMAT:
            raise StateRefused(f"its format is {doc.get('format')!r:.60}, not {FORMAT!r}")
        for key, want in (("application", self.application), ("component", self.component)):
            if doc.get(key) != want:
                raise StateRefused(f"it is the state of {key} {doc.get(key)!r:.60}, not {want!r}")
        self._verify(doc)
        state = doc.get("state")
        if not isinstance(state, dict) or set(state) - {"properties", "fields"}:
            raise StateRefused("its state is not an object of properties and fields")
        props = state.get("properties", {})
        fields = state.get("fields", {})
        if not isinstance(props, dict) or not isinstance(fields, dict):
            raise StateRefused("its properties or fields are not objects")
        typed_props: dict[str, object] = {}
        ignored = []
        for name, value in props.items():
            declared = self.declared.get(name)
            if declared is None:
                ignored.append(name)
                continue
            if declared.kind == "string" and isinstance(value, str):
                typed_props[name] = value  # as long as the file holds: code may set any string
                continue
            try:
                typed_props[name] = typed(declared, value)
            except ConfigurationError as err:
                raise StateRefused(f"its property {name!r}: {err.message}") from None
        return {"properties": typed_props, "fields": fields}, ignored

    def _verify(self, doc: dict[str, Any]) -> None:
        given = doc.get(SIGNATURE)
        if self.key is None:
            return  # no token: nothing to check it with (the run directory is yours alone)
        if not isinstance(given, str):
            raise StateRefused(
                "it is not signed, and this application has a token (ACORDCS_TOKEN): a file "
                "its container wrote is signed with it"
            )
        signed = {k: v for k, v in doc.items() if k != SIGNATURE}
        if not hmac.compare_digest(given, self._sign(signed)):
            raise StateRefused(
                "its signature does not match: it was not written by this application's "
                "containers with the token they have now (forged, edited, or written under another "
                "token)"
            )

    def _sign(self, doc: Mapping[str, Any]) -> str:
        assert self.key is not None
        return hmac.new(self.key, _canonical(doc), hashlib.sha256).hexdigest()

    def _refuse(self, why: str) -> None:
        aside = self.path.with_name(
            f"{self.path.name}.refused-{time.strftime('%Y%m%dT%H%M%S', time.gmtime())}"
            f"-{os.getpid()}"
        )
        try:
            os.rename(self.path, aside)
            kept = f"moved aside to {aside}"
        except OSError as err:
            self.writable = False
            kept = (
                f"it could not be moved aside ({err.strerror or err}), so it is left as it is and "
                "this run does not write the component's state"
            )
        self.say(
            f"warning: {self.component}: state file {self.path} refused: {why}; {kept}; the "
            "component starts from the model's initial values"
        )
        return None

    # ------------------------------------------------------------------------------ writing
    def document(self, state: Mapping[str, Any]) -> bytes:
        """The file's bytes for ``state`` (what :meth:`CtxComponent.save_state` gives): the
        model's properties and the state fields that are JSON, signed when there is a token.
        A value that is not (a NaN, an object) is left out, said once."""
        props: dict[str, object] = {}
        for name, value in state.get("properties", {}).items():
            if name in self.declared and self._json(value, f"property {name!r}"):
                props[name] = value
        fields = {
            name: value
            for name, value in state.get("fields", {}).items()
            if self._json(value, f"state field {name!r}")
        }
        doc: dict[str, Any] = {
            "format": FORMAT,
            "application": self.application,
            "component": self.component,
            "state": {"properties": props, "fields": fields},
        }
        if self.key is not None:
            doc[SIGNATURE] = self._sign(doc)
        return json.dumps(doc, indent=1, sort_keys=True, allow_nan=False).encode("ascii") + b"\n"

    def _json(self, value: object, what: str) -> bool:
        try:
            _canonical(value)
            return True
        except (TypeError, ValueError, RecursionError) as err:
            if what not in self._said:
                self._said.add(what)
                self.say(
                    f"warning: {self.component}: {what} is not kept in {self.path}: its value is "
                    f"not JSON ({type(err).__name__}: {err}); keep it a number, string, bool, "
                    "list or dict"
                )
            return False

    def write(self, state: Mapping[str, Any]) -> bool:
        """Replace the file with ``state`` at once (temporary file, fsync, rename, fsync of the
        directory); False when not written (too large or not writable: said). OSError as the
        file system raises it."""
        if not self.writable:
            return False
        data = self.document(state)
        if len(data) > self.limit:
            if "size" not in self._said:
                self._said.add("size")
                self.say(
                    f"warning: {self.component}: its state is {len(data):,} bytes, over the "
                    f"{self.limit:,} a state file may hold: not written to {self.path}"
                )
            return False
        fd, tmp = tempfile.mkstemp(
            dir=self.path.parent, prefix=f".{self.path.name}.", suffix=".tmp"
        )
        try:
            with os.fdopen(fd, "wb") as out:
                out.write(data)
                out.flush()
                os.fsync(out.fileno())
            os.replace(tmp, self.path)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise
        directory = os.open(self.path.parent, os.O_RDONLY | os.O_DIRECTORY)
        try:
            os.fsync(directory)
        finally:
            os.close(directory)
        return True


class Persistence:
    """Keeps the state files of the persistent components of ``container`` (``stores``, by
    component name): a writer thread writes a component's file after its properties changed, at
    most once per ``interval`` seconds; :meth:`close` writes each one last (after the components
    stopped: what their ``on_stop`` left). A write that fails is a fault of the container."""

    def __init__(
        self,
        container: Container,
        stores: Mapping[str, StateStore],
        *,
        interval: float = WRITE_INTERVAL,
    ) -> None:
        self.container = container
        self.stores = dict(stores)
        self.interval = interval
        self.writes = 0
        self._instances: dict[str, CtxComponent] = {}
        self._dirty: set[str] = set()
        self._wake = threading.Condition()
        self._closed = False
        self._dirty = set(self.stores)  # the first write at once: what on_start left
        for name in self.stores:
            self._instances[name] = container.instance(name)
            container.subscribe(ev.PROPERTY_CHANGED, self._changed, name=self._key, element=name)
            container.subscribe(ev.COMPONENT_REPLACED, self._replaced, name=self._key, element=name)
        self._thread = threading.Thread(
            target=self._run, name=f"state of {container.name}", daemon=True
        )
        self._thread.start()

    @property
    def _key(self) -> str:
        return f"persistence of {self.container.name}"

    def _changed(self, event: Event) -> None:
        if event.element in self._dirty:  # already due to be written: nothing to wake
            return
        with self._wake:
            self._dirty.add(event.element)
            self._wake.notify()

    def _replaced(self, event: Event) -> None:
        with contextlib.suppress(RuntimeFailure):
            self._instances[event.element] = self.container.instance(event.element)
        self._changed(event)

    def _run(self) -> None:
        while True:
            with self._wake:
                self._wake.wait_for(lambda: self._dirty or self._closed)
                if self._closed:
                    return
                names, self._dirty = self._dirty, set()
            for name in sorted(names):
                self._write(name)
            with self._wake:  # the coalescing: changes meanwhile wait for the next write
                self._wake.wait_for(lambda: self._closed, timeout=self.interval)

    def _write(self, name: str) -> None:
        instance = self._instances[name]
        try:
            if self.stores[name].write(self._snapshot(instance)):
                self.writes += 1
        except Exception as exc:  # the disk full, the run directory gone: said as a fault
            self.container.faults.record(
                "persistence",
                name,
                exc,
                self.container.clock.now(),
                file=str(self.stores[name].path),
            )

    @staticmethod
    def _snapshot(instance: CtxComponent) -> dict[str, Any]:
        """The component's state as it is now. Taken in the writer's thread while the component
        runs in others: a state field (a dict) that changed size while copied is copied again."""
        for _ in range(2):
            try:
                return instance.save_state()
            except RuntimeError:  # "dictionary changed size during iteration"
                continue
        return instance.save_state()

    def flush(self) -> None:
        """Write every component's file now (in the caller's thread)."""
        for name in sorted(self.stores):
            self._write(name)

    def close(self) -> None:
        """Stop the writer and write each file a last time."""
        with self._wake:
            if self._closed:
                return
            self._closed = True
            self._wake.notify_all()
        self._thread.join(timeout=10)
        self.container.unsubscribe(self._key)
        self.flush()
