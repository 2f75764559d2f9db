"""The running containers of a built application, found as its generated scripts find them
(:func:`acordcs.runtime.live.app_settings.settings` sources ``bin/env.sh`` as they do), so that
``ACORDCS_RUN_DIR=... acordcs-gen update`` reaches what ``bin/start-all`` started with the same
environment: :func:`reach` asks each container's management interface
(:mod:`acordcs.runtime.live.management`) which descriptor it runs, presenting the token."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from acordcs.runtime.live.app_settings import Settings


@dataclass
class Reached:
    """A container of the application, where the scripts say it serves: its management
    interface's ``uri``, and what it answered (``status``: see
    :meth:`~acordcs.runtime.live.management.Management.status`; its ``descriptor``) or why it did
    not (``problem``)."""

    name: str
    host: str
    port: str
    uri: str
    status: dict[str, Any] | None = None
    descriptor: str = ""
    problem: str = ""


def reach(found: Settings, *, timeout: float) -> list[Reached]:
    """Ask each container of ``found`` which descriptor it runs (see :class:`Reached`)."""
    from acordcs.runtime.connectors.remote import RemoteConnector
    from acordcs.runtime.errors import RuntimeFailure
    from acordcs.runtime.live.management_server import MANAGE_OBJECT

    connector = RemoteConnector(timeout=timeout, token=found.token or None)
    out = []
    try:
        for name, (host, port) in found.containers.items():
            uri = f"PYRO:{MANAGE_OBJECT.format(name)}@{host}:{port}"
            item = Reached(name, host, port, uri)
            out.append(item)
            where = f"container {name} at {host}:{port}"
            try:
                item.status = connector.request(uri, "status", where=where, what="a status")
                item.descriptor = connector.request(uri, "descriptor", where=where)
            except RuntimeFailure as err:
                item.problem = _why(err.message)
    finally:
        connector.close()
    return out


def _why(message: str) -> str:
    if "unknown object" in message:
        return (
            "it answers but has no management interface (started by an acordcs without "
            "acordcs-gen update): restart it to update it"
        )
    if "handshake refused" in message or "wrong or missing token" in message:
        return (
            "it refused the token (ACORDCS_TOKEN, or the token file of the run directory): it "
            "was started with another one; use the same ACORDCS_RUN_DIR or ACORDCS_TOKEN as "
            "when it was started"
        )
    if message.startswith("no reply to "):  # connected, then nothing came back in time
        return _answers_none(message)
    if "cannot reach" in message:
        said = message.split(": ", 1)[-1]
        if "receiving" in said and "timeout" in said:
            return _answers_none(said)
        if "timeout" in said or "timed out" in said:
            return (
                f"it does not answer within the timeout ({said}): no connection was made (its "
                "host is down or unreachable, or a firewall drops the connection); check the "
                "host and port its scripts give it"
            )
        return f"not running (nothing answers: {said})"
    return message


def _answers_none(said: str) -> str:
    """A container that took the connection (in the handshake or after it) and sent nothing
    back in time: one meaning, whichever call found it."""
    return (
        f"it does not answer within the timeout ({said}): it takes connections but answers "
        "none (stopped by a signal such as SIGSTOP, overloaded, or hung); resume it (kill -CONT "
        "PID), or wait and run the command again (--timeout gives it longer)"
    )


def apply(
    item: Reached,
    descriptor: str,
    expected: str,
    remote: dict[str, str],
    reset: bool,
    code: list[str],
    *,
    token: str,
    timeout: float,
) -> dict[str, Any]:
    """Send the new ``descriptor`` to ``item``'s management interface, with the elements whose
    code changed (``code``; see :meth:`~acordcs.runtime.live.management.Management.apply`); a
    failure to reach it is a refusal."""
    from acordcs.runtime.connectors.remote import RemoteConnector
    from acordcs.runtime.errors import RuntimeFailure

    connector = RemoteConnector(timeout=timeout, token=token or None)
    try:
        reply: dict[str, Any] = connector.request(
            item.uri,
            "apply",
            descriptor,
            expected,
            remote,
            reset,
            *([code] if code else []),  # none: what a container of an earlier acordcs takes
            where=f"container {item.name} at {item.host}:{item.port}",
            what="the update",
        )
        return reply
    except RuntimeFailure as err:
        return {
            "status": "unreachable",
            "error": _why(err.message),
            "applied": [],
            "kept": [],
            "rolled_back": [],
            "unrolled": [],
        }
    finally:
        connector.close()


def container_uri(name: str, host: str, port: str, object_name: str | None = None) -> str:
    """The URI of container ``name``'s endpoint, as its start script gives it to the others."""
    return f"PYRO:{object_name or f'acordcs.container.{name}'}@{host}:{port}"
