"""The running containers of a built application, found as its generated scripts find them.

The scripts of the ``shell`` target (``bin/``) take their settings from ``bin/env.sh``: the run
directory, the application's token, each container's host and port, each with its default and
the environment winning over it. Rather than restating those rules, :func:`settings` sources
``env.sh`` in ``sh`` as the scripts do (same environment, same working directory) and reads back
what it set, so that ``ACORDCS_RUN_DIR=... acordcs-gen update`` reaches what ``bin/start-all``
started with the same environment. :func:`reach` then asks each container's management interface
(:mod:`acordcs.runtime.live.management`) which descriptor it runs, presenting the token.
"""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from acordcs.errors import AcordError

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")

# Sourced as a script of bin/ sources it ($bin set), then each value NUL-terminated (a value may
# hold any other character). "$@": the containers whose host and port are wanted.
_READ = r"""
bin=$1
shift
. "$bin/env.sh" || exit 2
printf '%s\0' "$ACORDCS_RUN_DIR" "${ACORDCS_TOKEN-}" "$ACORDCS_PACKAGE"
for c; do
    eval "printf '%s\0%s\0' \"\${ACORDCS_${c}_HOST-}\" \"\${ACORDCS_${c}_PORT-}\""
done
"""


class NotFound(AcordError):
    """No application to update in the directory, or its scripts refuse their settings."""

    exit_code = 2


@dataclass(frozen=True)
class Settings:
    """What ``bin/env.sh`` sets: the run directory, the token, the package, and each container's
    host and port (``containers``: name -> (host, port))."""

    run_dir: str
    token: str
    package: str
    containers: dict[str, tuple[str, str]] = field(default_factory=dict)


def _source(app: Path, names: list[str], timeout: float) -> list[str]:
    env_sh = app / "bin" / "env.sh"
    if not env_sh.is_file():
        raise NotFound(
            f"{app} has no bin/env.sh: not an application built by acordcs-gen build (the "
            "shell target writes it), so no container of it can be found",
            hint="build it (acordcs-gen build MODEL -o DIR), start it (DIR/bin/start-all), then "
            "update it",
        )
    try:
        done = subprocess.run(
            ["sh", "-c", _READ, "acordcs-gen update", str(env_sh.parent.resolve()), *names],
            capture_output=True,
            timeout=timeout,
            check=False,
        )
    except (OSError, subprocess.TimeoutExpired) as err:
        raise NotFound(f"{env_sh}: cannot source it in sh: {err}") from None
    if done.returncode != 0:
        said = done.stderr.decode("utf-8", "replace").strip() or f"exit {done.returncode}"
        raise NotFound(
            f"{env_sh} refused its settings: {said}",
            hint="fix what it says, as its scripts would need it to start the application",
        )
    values = done.stdout.decode("utf-8", "surrogateescape").split("\0")
    if len(values) < 3 + 2 * len(names):
        raise NotFound(f"{env_sh}: sourcing it printed something else than its settings")
    return values


def settings(app: Path, *, timeout: float = 10.0) -> Settings:
    """What ``app/bin/env.sh`` sets, sourced in ``sh`` (see the module docstring), for the
    containers of the descriptor the application directory holds (what its scripts start)."""
    from acordcs.descriptor import DescriptorError, from_xml
    from acordcs.generator.paths import read_bounded

    run_dir, token, package = _source(app, [], timeout)[:3]
    if not _IDENTIFIER.match(package):
        raise NotFound(f"{app / 'bin' / 'env.sh'}: ACORDCS_PACKAGE is {package!r}, not a package")
    path = app / package / "descriptor.xml"
    try:
        data = read_bounded(path)  # a FIFO or a huge file: refused at once, never waited on
        names = [c.name for c in from_xml(data, file=str(path)).containers]
    except (OSError, DescriptorError) as err:
        raise NotFound(
            f"{path}: cannot read the descriptor the application was built with: {err}",
            hint="build the application (acordcs-gen build) and start it first",
        ) from None
    names = [n for n in names if _IDENTIFIER.match(n)]  # the scripts' names are identifiers
    values = _source(app, names, timeout)
    hosts = {n: (values[3 + 2 * i], values[4 + 2 * i]) for i, n in enumerate(names)}
    return Settings(run_dir, token, package, hosts)


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
    from acordcs.runtime.live.management import MANAGE_OBJECT

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
