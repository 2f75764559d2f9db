"""A container's management interface (:class:`~.management.Management`) served over Pyro5: the
endpoint beside the container's own, at ``acordcs.manage.<container>`` of the same daemon (the
same token admits callers; serpent only; each argument checked before it reaches the
management), and :func:`manage`, which serves it and the container's observer interface as the
launcher does."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from acordcs.runtime import events as ev
from acordcs.runtime.connectors.pyrogate import serpent_only
from acordcs.runtime.connectors.remote import RemoteFault
from acordcs.runtime.errors import RuntimeFailure
from acordcs.runtime.live.management import Management
from acordcs.runtime.live.observer import OBSERVE_OBJECT, Observer, ObserverEndpoint

if TYPE_CHECKING:
    from acordcs.runtime.assembly import RunningApplication
    from acordcs.runtime.connectors.endpoint import ContainerServer
    from acordcs.runtime.events import Event
    from acordcs.runtime.live.update_steps import Classes

MANAGE_OBJECT = "acordcs.manage.{}"
"""The Pyro5 object name of a container's management interface."""


class ManagementEndpoint:
    """:class:`~.management.Management` over Pyro5 (see the module docstring); failures come back as
    :class:`~.connectors.remote.RemoteFault`."""

    def __init__(self, management: Management) -> None:
        self._management = management

    @serpent_only
    def status(self) -> dict[str, Any]:
        return self._guarded(self._management.status)

    @serpent_only
    def properties(self, elements: list[str]) -> dict[str, dict[str, Any]]:
        if not isinstance(elements, list | tuple):
            raise RemoteFault("TypeError", "elements is a list of element names", None)
        return self._guarded(lambda: self._management.properties(list(elements)))

    @serpent_only
    def descriptor(self) -> str:
        """The descriptor the container runs, as XML text."""
        return self._guarded(lambda: self._management.data.decode("utf-8"))

    @serpent_only
    def apply(
        self,
        descriptor: str,
        expected: str,
        remote: dict[str, str],
        reset: bool,
        code: list[str] | tuple[str, ...] = (),
    ) -> dict[str, Any]:
        if not isinstance(descriptor, str) or not isinstance(expected, str):
            raise RemoteFault("TypeError", "the descriptor and digest are text", None)
        if not isinstance(remote, dict) or not all(
            isinstance(k, str) and isinstance(v, str) for k, v in remote.items()
        ):
            raise RemoteFault("TypeError", "remote maps container names to URIs (text)", None)
        if not isinstance(code, list | tuple) or not all(isinstance(n, str) for n in code):
            raise RemoteFault("TypeError", "code is a list of element names (text)", None)
        return self._guarded(
            lambda: self._management.apply(
                descriptor, expected, remote, bool(reset), tuple(code)[:10000]
            )
        )

    @serpent_only
    def set_property(self, element: str, attribute: str, value: Any) -> dict[str, Any]:
        if not isinstance(element, str) or not isinstance(attribute, str):
            raise RemoteFault("TypeError", "set_property(element, attribute, value)", None)
        return self._guarded(lambda: self._management.set_property(element, attribute, value))

    @serpent_only
    def hold(self, component: str, seconds: float) -> dict[str, Any]:
        if not isinstance(component, str) or isinstance(seconds, bool):
            raise RemoteFault("TypeError", "hold(component name, seconds)", None)
        if not isinstance(seconds, int | float) or not math.isfinite(seconds):
            raise RemoteFault("TypeError", "seconds is a finite number", None)
        return self._guarded(lambda: self._management.hold(component, float(seconds)))

    @serpent_only
    def release(self, component: str) -> dict[str, Any]:
        if not isinstance(component, str):
            raise RemoteFault("TypeError", "release(component name)", None)
        return self._guarded(lambda: self._management.release(component))

    @staticmethod
    def _guarded(call: Any) -> Any:
        try:
            return call()
        except Exception as exc:  # including faults of our own: the worker must survive
            hint = exc.hint if isinstance(exc, RuntimeFailure) else None
            raise RemoteFault(type(exc).__name__, str(exc), hint) from None


def manage(
    running: RunningApplication,
    container: str,
    server: ContainerServer,
    descriptor: bytes,
    classes: Classes,
    remote: Mapping[str, str] | None = None,
    *,
    without_token: bool = False,
    timeout: float = 5.0,
    code: Mapping[str, Mapping[str, str]] | None = None,
    announce: bool = True,
) -> Management:
    """Serve the management of ``container`` (run from ``descriptor``, its new code from
    ``classes``: the launcher gives its package's, :class:`~.reloading.PackageClasses`) on
    ``server``'s daemon, as the launcher does; the log (standard output) gets a line with the
    digest of the descriptor it runs, at start (unless ``announce`` is false: the caller says it
    once it has started, :func:`say_digest`) and after each update, and one per change applied
    (``model.updated``); ``code``: the user's files as the container loaded them. Without a token, it takes updates only on a loopback host and with
    ``without_token``. Its observer interface (:class:`~.observer.Observer`) is served beside it,
    at ``acordcs.observe.<container>``: ``management.observer``."""
    from acordcs.runtime.connectors.pyrogate import is_loopback

    refusal = None
    if not server.token_required and not (without_token and is_loopback(server.host)):
        refusal = (
            f"container {container!r} was started without a token (ACORDCS_TOKEN): it takes no "
            "update; start it with the application's token (bin/<container>-start sets it), or "
            "on a loopback host with --updates-without-token"
        )
    management = Management(
        running,
        container,
        descriptor,
        classes=classes,
        remote=remote,
        refusal=refusal,
        remote_timeout=timeout,
        code=code,
    )
    server.daemon.register(ManagementEndpoint(management), MANAGE_OBJECT.format(container))
    management.refused = server.refused
    management.observer = Observer(running.container(container), management.policy_sets)
    server.daemon.register(ObserverEndpoint(management.observer), OBSERVE_OBJECT.format(container))
    box = running.container(container)

    def updated(event: Event) -> None:
        print(f"{container}: t={box.clock.now():.3f} s: model.updated: {event.value}", flush=True)

    box.subscribe(ev.MODEL_UPDATED, updated, name="log")
    management.on_applied = lambda value: say_digest(container, value, "now runs")
    if announce:
        say_digest(container, management.digest, "runs")
    return management


def say_digest(container: str, value: str, verb: str) -> None:
    """The log line giving the digest of the descriptor a container runs."""
    print(f"{container}: {verb} descriptor sha256 {value}", flush=True)
