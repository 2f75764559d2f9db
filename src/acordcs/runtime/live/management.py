"""A running container's management interface: what ``acordcs-gen update`` talks to.

:class:`Management` keeps, for one container of a running application, the descriptor it runs
(its bytes, and their sha256: the *digest* the launcher prints and ``status`` returns), which
properties were changed at run time (so that an update leaves their values alone), and applies
an update's part to the container (:func:`acordcs.runtime.live.apply_update.apply_part`), one update at a
time: given the new descriptor and the digest the caller believes the container runs (another
update in between is refused), it computes the plan (:func:`acordcs.descriptor.diff.diff`),
refuses a part that cannot apply live, applies it or rolls it back, and from then on runs the new
descriptor.

:class:`~.management_server.ManagementEndpoint` (:mod:`.management_server`) serves it over
Pyro5 beside the container's endpoint, at the object ``acordcs.manage.<container>`` of the same
daemon: the same token admits callers (the handshake
of :mod:`.connectors.pyrogate`), calls in serpent only, and only its methods are exposed:
``status``, ``descriptor``, ``properties``, ``apply``, ``set_property``, ``hold`` and
``release``. A container
served without a token refuses updates and holds unless it was started with updates allowed
explicitly on a loopback host (``--updates-without-token``). :func:`~.management_server.manage` also serves the
container's observer interface beside it (:mod:`.observer`: its context and policy firings, for a
console).

``hold(component, seconds)`` pauses the callers of a component from other processes
(:mod:`.holds`): a call
arriving from another process while the hold lasts waits until it is released or ends (never
longer than :data:`HOLD_PATIENCE` times the container's remote-call timeout, so that its caller,
whose calls time out after the same number of seconds when the generated scripts start them, gets
an answer in time; it then goes through). A hold lasts ``seconds`` (at most :data:`HOLD_MAX`):
whoever holds renews it, so a holder that went away frees the component soon. Calls made in this
container (by a component, a monitor, a policy set) are never held. The WebLab console holds the
Vision component while a viewer drives: the Navigator of the other process waits for its next
image, between two of its cycles.
"""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from acordcs.runtime import events as ev
from acordcs.runtime.errors import ConfigurationError, RuntimeFailure
from acordcs.runtime.live.apply_update import UpdateFailed, apply_part
from acordcs.runtime.live.code_check import hosted_here
from acordcs.runtime.live.holds import CallHold, HoldNotices
from acordcs.runtime.live.observer import Observer
from acordcs.runtime.live.property_setting import model_property, typed
from acordcs.runtime.live.update_steps import Classes

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application
    from acordcs.descriptor.diff import Change
    from acordcs.runtime.assembly import RunningApplication
    from acordcs.runtime.events import Event

HOLD_MAX = 60.0
"""Seconds one hold lasts at most; renew it to hold longer."""

HOLD_PATIENCE = 0.75
"""The share of the container's remote-call timeout a held call waits at most."""


def digest(data: bytes) -> str:
    """The digest of a descriptor: the sha256 of its bytes, in hexadecimal."""
    return hashlib.sha256(data).hexdigest()


class Management:
    """The management of container ``container`` of ``running``, which runs the descriptor
    ``descriptor`` (the bytes it was read from). ``classes``: where new code comes from;
    ``remote``: the URIs of the other containers it was started with; ``refusal``: why it refuses
    updates (None: it takes them); ``code``: the user's files of its components and monitors as
    it loaded them (:meth:`~acordcs.runtime.live.update_steps.Classes.code`)."""

    def __init__(
        self,
        running: RunningApplication,
        container: str,
        descriptor: bytes,
        *,
        classes: Classes,
        remote: Mapping[str, str] | None = None,
        refusal: str | None = None,
        remote_timeout: float = 5.0,
        token: str | None = None,
        code: Mapping[str, Mapping[str, str]] | None = None,
    ) -> None:
        self.running = running
        self.name = container
        self.container = running.container(container)
        self.data = descriptor
        self.digest = digest(descriptor)
        self.application: Application = running.descriptor
        self.classes = classes
        self.remote = dict(remote or {})
        self.refusal = refusal
        self.remote_timeout = remote_timeout
        self.token = token
        self.updates = 0
        self.last_update: dict[str, Any] | None = None
        # The user's files of its components and monitors as it loaded them (Classes.code).
        self.code: dict[str, dict[str, str]] = {n: dict(v) for n, v in (code or {}).items()}
        # Called with the new digest once an update applied (the launcher logs it).
        self.on_applied: Callable[[str], None] | None = None
        # Its observer interface, when served (manage() makes it).
        self.observer: Observer | None = None
        # The connections the daemon serving it refused, by why (manage() gives it).
        self.refused: Callable[[], dict[str, int]] | None = None
        self._lock = threading.Lock()
        self._applying: int | None = None  # the thread applying an update
        # (element, attribute) of the properties changed at run time: an update leaves them be;
        # those a persistent component's kept state set at start are.
        self._touched: set[tuple[str, str]] = set(running.restored.get(container, ()))
        self._holds: dict[str, CallHold] = {}
        self._holding = threading.Lock()
        self.hold_notices = HoldNotices(self._notice)
        self.container.subscribe(ev.PROPERTY_CHANGED, self._changed, name="management")

    def _changed(self, event: Event) -> None:
        # An update's own writes are not changes at run time; what a policy set writes on them,
        # in the same thread, is (its events carry the set as their origin).
        mine = self._applying == threading.get_ident() and event.origin is None
        if not mine and event.attribute is not None:
            self._touched.add((event.element, event.attribute))

    def touched(self, element: str, attribute: str) -> bool:
        """Whether property ``element.attribute`` was changed at run time (by anything but an
        update) since the container started."""
        return (element, attribute) in self._touched

    def policy_sets(self) -> tuple[str, ...]:
        """The names of the policy sets the container hosts, as the descriptor it runs says."""
        here = next((c for c in self.application.containers if c.name == self.name), None)
        return tuple(here.hosted("policy-set")) if here is not None else ()

    def _notice(self, kind: str, element: str, value: object, data: dict[str, object]) -> None:
        if self.observer is not None:
            self.observer.notice(kind, element, value, data)

    def close(self) -> None:
        self.hold_notices.close()
        self.container.unsubscribe("management")
        self.container.unsubscribe("management:fired")
        if self.observer is not None:
            self.observer.close()
        with self._holding:
            holds, self._holds = dict(self._holds), {}
        for hold in holds.values():
            hold.end()
            self.container.remove_interceptor(hold)

    # -------------------------------------------------------------------------------- calls
    def status(self) -> dict[str, Any]:
        """The container, its application, the digest of the descriptor it runs, the updates
        applied since it started, whether it takes updates (``refusal``: why not), its clock's
        ``time``, per policy set how often it ``fires`` and its last firing (``time``,
        ``inputs``, ``outputs``), when the ``last_update`` started and was applied, and when
        each policy set it replanned fired last before it and first after it (clock times), and
        the user's files of its components and monitors as it loaded them (``code``: element ->
        ``kind``, ``file`` from the application's directory, ``sha256``), and the connections
        ``refused`` by the Pyro5 daemon serving it (its endpoint, this interface and its
        observer's), by why: ``wrong_token`` (empty when not served), and the ``holds`` lasting
        now (each as :meth:`hold` returns it)."""
        sets: dict[str, Any] = {}
        for name in self.policy_sets():
            try:
                found = self.container.policy_set(name)
            except RuntimeFailure:
                continue
            firing = found.last_firing
            sets[name] = {
                "fires": found.fires,
                "time": firing.time if firing is not None else None,
                "inputs": _plain(firing.inputs) if firing is not None else {},
                "outputs": _plain(firing.outputs) if firing is not None else {},
            }
        return {
            "container": self.name,
            "application": self.application.name,
            "digest": self.digest,
            "updates": self.updates,
            "refusal": self.refusal,
            "time": self.container.clock.now(),
            "policy_sets": sets,
            "last_update": self.last_update,
            "code": {n: dict(v) for n, v in self.code.items()},
            "refused": self.refused() if self.refused is not None else {},
            "holds": self._held(),
        }

    def _held(self) -> list[dict[str, Any]]:
        with self._holding:
            holds = list(self._holds.values())
        return [state for state in (h.state() for h in holds) if state["left"] > 0]

    def properties(self, elements: list[str]) -> dict[str, dict[str, Any]]:
        """The properties of ``elements`` (components, ``Component.Port``, connections, monitors,
        the container) as they are now; an element it does not have is left out."""
        found = self.container.elements()
        return {e: _plain(found[e]) for e in elements if isinstance(e, str) and e in found}

    def set_property(self, element: str, attribute: str, value: object) -> dict[str, Any]:
        """Set property ``element.attribute`` of the model the container runs to ``value``,
        typed by its kind (:mod:`.property_setting`); refused as updates are. A change at run
        time: an update leaves it be. Returns the ``value`` set and the ``old`` one."""
        if self.refusal is not None:
            raise ConfigurationError(
                self.refusal.replace(
                    "it takes no update", "it takes no update and sets no property"
                )
            )
        prop = model_property(self.application, self.name, element, attribute)
        new = typed(prop, value)
        old = self.container.get_property(element, attribute)
        self.container.set_property(element, attribute, new)
        return {
            "element": element,
            "attribute": attribute,
            "value": new,
            "old": _plain({"": old})[""],
        }

    def hold(self, component: str, seconds: float) -> dict[str, Any]:
        """Hold the calls other processes make to ``component`` for ``seconds`` (see the module
        docstring; again while held: renewed). Returns the ``component``, the seconds the hold
        has ``left``, the calls ``waiting`` now and the ``patience`` of each (seconds)."""
        if self.refusal is not None:
            raise ConfigurationError(
                self.refusal.replace("it takes no update", "it takes no update and holds no call")
            )
        if not isinstance(seconds, int | float) or not 0 < seconds <= HOLD_MAX:
            raise ConfigurationError(f"a hold lasts more than 0 and at most {HOLD_MAX:g} seconds")
        if not self.container.operations_of(component):
            names = [c.name for c in self.container.components()]
            if component in names:  # hosted, but nothing to hold: no call can reach it
                raise ConfigurationError(
                    f"component {component!r:.80} of container {self.name!r} provides no "
                    "operation, so no call to it can be held",
                    hint="hold a component that provides operations",
                )
            raise ConfigurationError(
                f"container {self.name!r} hosts no component {component!r:.80} (it hosts: "
                f"{', '.join(names) or 'none'})",
                hint="hold a component of the container it runs in",
            )
        with self._holding:
            found = self._holds.get(component)
            if found is None:
                found = CallHold(component, HOLD_PATIENCE * self.remote_timeout)
                self._holds[component] = found
                self.container.add_interceptor(found, component=component)
        found.extend(float(seconds))
        self.hold_notices.held(found, float(seconds))
        return found.state()

    def release(self, component: str) -> dict[str, Any]:
        """End the hold on ``component`` (its waiting calls go on); ``held`` says whether there
        was one."""
        with self._holding:
            found = self._holds.pop(component, None)
        if found is None:
            return {"component": component, "held": False, "left": 0.0, "waiting": 0}
        found.end()
        self.container.remove_interceptor(found)
        self.hold_notices.ended(found, "released")
        return {**found.state(), "held": True}

    def apply(
        self,
        descriptor: str,
        expected: str,
        remote: Mapping[str, str] | None = None,
        reset: bool = False,
        code: Sequence[str] = (),
    ) -> dict[str, Any]:
        """Apply the new ``descriptor`` (its XML text) to the container, which must run the
        descriptor of digest ``expected``; ``remote``: URIs of other containers (only those it
        reaches in the new model are used; those it was started with win); ``reset``: set new
        defaults also over values changed at run time; ``code``: the components and monitors
        hosted here whose code (the user's file) changed, replaced by their classes read afresh
        keeping their state (``~ code of component C``), also when the descriptor is the one it
        runs.

        Returns ``status`` (``applied``, ``unchanged``, ``refused`` or ``rolled back``), the
        plan lines ``applied``, the defaults ``kept``, ``rolled_back`` and ``unrolled`` (undone,
        and what could not be), ``error`` (why refused or what failed), the container's
        ``digest`` after it and the ``seconds`` the part took."""
        if self.refusal is not None:
            return self._reply("refused", error=self.refusal)
        if not self._lock.acquire(blocking=False):
            return self._reply(
                "refused", error="another update is being applied to it: try again when it is done"
            )
        try:
            return self._apply(descriptor, expected, dict(remote or {}), reset, tuple(code))
        finally:
            self._lock.release()

    def _reply(self, status: str, **fields: Any) -> dict[str, Any]:
        out: dict[str, Any] = {
            "container": self.name,
            "status": status,
            "digest": self.digest,
            "applied": [],
            "kept": [],
            "rolled_back": [],
            "unrolled": [],
            "error": None,
            "seconds": 0.0,
        }
        out.update(fields)
        return out

    def _apply(
        self,
        descriptor: str,
        expected: str,
        remote: dict[str, str],
        reset: bool,
        code: tuple[str, ...],
    ) -> dict[str, Any]:
        from acordcs.descriptor import DescriptorError, from_xml
        from acordcs.descriptor.diff import diff

        if expected != self.digest:
            return self._reply(
                "refused",
                error=f"it runs descriptor {self.digest[:12]}, not {expected[:12]}: it changed "
                "since the plan was made; run the update again",
            )
        data = descriptor.encode("utf-8")
        try:
            new = from_xml(data, file=f"the descriptor sent to container {self.name}")
        except DescriptorError as err:
            return self._reply("refused", error=str(err))
        part = diff(self.application, new).part(self.name)
        coded = self._code_changes(new, part, code)
        if isinstance(coded, str):
            return self._reply("refused", error=coded)
        part += coded
        fixed = [c for c in part if not c.live]
        if fixed:
            return self._reply(
                "refused", error=f"{fixed[0].line}: cannot apply live ({fixed[0].why})"
            )
        # What its start script would give it (the containers it reaches in the new model),
        # those it was started with winning.
        mine = next((c for c in new.containers if c.name == self.name), None)
        reaches = set(mine.reaches) if mine is not None else set()
        remotes = {n: u for n, u in remote.items() if n in reaches}
        remotes.update(self.remote)
        sets = {c.element for c in part if c.kind == "policy set" and c.action in ("add", "replan")}
        started = self.container.clock.now()
        before = {n: self._last_fired(n) for n in sets}
        self._applying = threading.get_ident()
        try:
            outcome = apply_part(
                self.running,
                self.name,
                self.application,
                new,
                part,
                classes=self.classes,
                touched=self.touched,
                remote=remotes,
                reset=reset,
                remote_timeout=self.remote_timeout,
                token=self.token,
            )
        except UpdateFailed as err:
            return self._reply(
                "rolled back",
                error=err.message,
                rolled_back=list(err.rolled_back),
                unrolled=list(err.unrolled),
            )
        finally:
            self._applying = None
        self.application, self.data, self.digest = new, data, digest(data)
        here = set(hosted_here(new, self.name, "component"))
        here |= set(hosted_here(new, self.name, "monitor"))
        self.code = {n: v for n, v in self.code.items() if n in here}
        self.code.update(outcome.code)
        self.updates += 1
        self._watch(started, before)
        if self.on_applied is not None:
            self.on_applied(self.digest)
        return self._reply(
            "applied" if part else "unchanged",
            applied=outcome.applied,
            kept=outcome.kept,
            seconds=outcome.seconds,
        )

    def _code_changes(
        self, new: Application, part: tuple[Change, ...], code: tuple[str, ...]
    ) -> tuple[Change, ...] | str:
        """The changes of the code of ``code`` (element names) in the container's part, or why
        they are refused (an element it does not host in the new descriptor)."""
        from acordcs.descriptor.diff import code_change

        kinds = {n: "component" for n in hosted_here(new, self.name, "component")}
        kinds.update((n, "monitor") for n in hosted_here(new, self.name, "monitor"))
        added = {c.element for c in part if c.action == "add"}
        out = []
        for name in dict.fromkeys(code):
            if name not in kinds:
                return (
                    f"code of {name!r:.80}: container {self.name!r} hosts no component or "
                    "monitor of that name in the new descriptor"
                )
            if name not in added:  # an element added is read afresh anyway
                out.append(code_change(kinds[name], name, self.name))
        return tuple(out)

    # ------------------------------------------------------------ when an update took effect
    def _last_fired(self, name: str) -> float | None:
        try:
            firing = self.container.policy_set(name).last_firing
        except RuntimeFailure:
            return None
        return firing.time if firing is not None else None

    def _watch(self, started: float, before: dict[str, float | None]) -> None:
        """Note when the update started and was applied (the container's clock) and, for each
        policy set it gave a plan, when it fired last before and first after (``status``'s
        ``last_update``): listening to ``policy.fired`` only until each has fired."""
        self.container.unsubscribe("management:fired")
        first: dict[str, float] = {}
        self.last_update = {
            "started": started,
            "applied": self.container.clock.now(),
            "fired_before": before,
            "first_fired": first,
        }
        if not before:
            return

        def fired(event: Event) -> None:
            if event.element in before and event.element not in first:
                first[event.element] = event.time
                if len(first) == len(before):
                    self.container.unsubscribe("management:fired")

        self.container.subscribe(ev.POLICY_FIRED, fired, name="management:fired")


def _plain(values: Mapping[str, object]) -> dict[str, Any]:
    """``values`` as serpent carries them: numbers, text and booleans as they are, others shown."""
    return {
        str(k): v if isinstance(v, bool | int | float | str) or v is None else repr(v)
        for k, v in values.items()
    }
