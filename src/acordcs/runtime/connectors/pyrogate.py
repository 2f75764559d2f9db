"""Who may talk to a container's Pyro5 endpoint, with Pyro5's own means (see docs/providers.md,
"Security model: the Pyro5 endpoint").

- a **token** per application, sent by every proxy in Pyro5's connection handshake
  (``_pyroHandshake``) and checked by the daemon's ``validateHandshake`` before any call can be
  made: from the ``token=`` argument of :class:`~.endpoint.ContainerServer`,
  :class:`~.remote.RemoteConnector` and ``assemble``, else the environment variable
  ``ACORDCS_TOKEN`` (:data:`TOKEN_ENV`);
- a **handshake deadline**: a connection that has not completed the handshake within
  ``handshake_timeout`` seconds is closed, so idle TCP connections cannot hold the daemon's workers;
  a connection that passed the handshake has no idle limit (its proxy keeps it for the next call);
- **serpent only**: a call made with another serializer (marshal, json, msgpack) is refused;
- the daemon's own object lists nothing (``registered``/``info`` are refused);
- optional **TLS** (:class:`TLSFiles`), with client certificates when the server names the CA
  that signs them;
- **refusals counted, the log bounded**: every refused connection (a wrong or missing token, no
  valid handshake within the deadline, no free worker) is counted by kind
  (:attr:`GatedDaemon.refusals`, in the management interface's ``status``) and logged on the 1st,
  2nd, 4th, 8th... of its kind only, with the peer's address (:mod:`acordcs.runtime.refusals`).

Pyro5 5.17 keeps its configuration (the handshake deadline ``COMMTIMEOUT``, the worker pool size
``THREADPOOL_SIZE``, and SSL with its cached contexts) per process, not per daemon: the settings
here apply to every Pyro5 daemon and proxy of the process.
"""

from __future__ import annotations

import hmac
import ipaddress
import logging
import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

import Pyro5.api
import Pyro5.callcontext
import Pyro5.errors
import Pyro5.serializers
import Pyro5.server

from acordcs.runtime.errors import ConfigurationError
from acordcs.runtime.refusals import Refusals, peer_address

TOKEN_ENV = "ACORDCS_TOKEN"
"""The environment variable holding the application's token when no ``token=`` is given."""

HANDSHAKE_TIMEOUT = 2.0
"""Seconds a new connection has to complete the handshake (Pyro5's ``COMMTIMEOUT``)."""

MAX_CONNECTIONS = 256
"""Connections a daemon serves at once (Pyro5's ``THREADPOOL_SIZE``; one worker thread each,
created on demand). Beyond it, a new connection is refused until one closes or times out."""

SERPENT_ID = Pyro5.serializers.SerpentSerializer.serializer_id
log = logging.getLogger(__name__)
F = TypeVar("F", bound=Callable[..., Any])


def resolve_token(token: str | None) -> str | None:
    """``token``, else ``$ACORDCS_TOKEN``, else None (no authentication)."""
    if token is None:
        token = os.environ.get(TOKEN_ENV) or None
    if token is not None and (not isinstance(token, str) or not token):
        raise ConfigurationError(
            "the remote endpoint's token must be a non-empty string",
            hint=f"pass token='...' or set {TOKEN_ENV}",
        )
    return token


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


@dataclass(frozen=True)
class TLSFiles:
    """TLS for the Pyro5 endpoint (PEM files).

    On a server: ``cert`` and ``key`` are the server's; with ``cacerts``, clients must present a
    certificate signed by it (mutual TLS). On a client (:class:`~.remote.RemoteConnector`):
    ``cacerts`` verifies the server (its certificate must name the host the URI gives), ``cert``
    and ``key`` are the client's certificate, when the server asks for one.
    """

    cert: str = ""
    key: str = ""
    cacerts: str = ""

    def configure(self, *, server: bool) -> None:
        """Set Pyro5's (process-wide) SSL configuration for this side."""
        for path in (self.cert, self.key, self.cacerts):
            if path and not os.path.exists(path):
                raise ConfigurationError(
                    f"TLS file {path!r} does not exist",
                    hint="give the PEM files of the certificate, key and CA",
                )
        cfg = Pyro5.api.config
        cfg.SSL = True
        cfg.SSL_CACERTS = self.cacerts
        if server:
            if not self.cert:
                raise ConfigurationError(
                    "a TLS server needs its certificate (TLSFiles(cert=..., key=...))"
                )
            cfg.SSL_SERVERCERT, cfg.SSL_SERVERKEY = self.cert, self.key
            cfg.SSL_REQUIRECLIENTCERT = bool(self.cacerts)
        else:
            cfg.SSL_CLIENTCERT, cfg.SSL_CLIENTKEY = self.cert, self.key


def not_serpent(used: int) -> Pyro5.errors.SecurityError:
    """The refusal of a call that arrived with serializer ``used``, not serpent."""
    return Pyro5.errors.SecurityError(
        f"this endpoint accepts the serpent serializer only (the call used id {used})"
    )


def serpent_only(method: F) -> F:
    """Refuse a call that arrived with another serializer than serpent (Pyro5 lets the client
    choose; marshal and json would bypass what the endpoint promises about its arguments)."""

    def checked(*args: Any, **kwargs: Any) -> Any:
        used = getattr(Pyro5.callcontext.current_context, "serializer_id", SERPENT_ID)
        if used != SERPENT_ID:
            raise not_serpent(used)
        return method(*args, **kwargs)

    checked.__name__, checked.__doc__ = method.__name__, method.__doc__
    return Pyro5.api.expose(checked)  # type: ignore[no-any-return]


class QuietDaemonObject(Pyro5.server.DaemonObject):
    """The daemon's own object, minus the listing of what is registered."""

    @Pyro5.api.expose
    def registered(self) -> list[str]:
        raise Pyro5.errors.SecurityError("this daemon does not list its objects")

    @Pyro5.api.expose
    def info(self) -> str:
        raise Pyro5.errors.SecurityError("this daemon does not describe itself")


class GatedDaemon(Pyro5.api.Daemon):
    """A Pyro5 daemon admitting only connections that present ``token`` in the handshake;
    ``name`` names what it serves in the log lines of its refusals (:attr:`refusals`)."""

    def __init__(
        self, *, host: str, port: int, token: str | None, name: str = "a Pyro5 endpoint"
    ) -> None:
        self._token = token.encode() if token is not None else None
        super().__init__(host=host, port=port, interface=QuietDaemonObject)
        self.refusals = Refusals(
            log,
            f"{name} (Pyro5 endpoint {self.locationStr})",
            {"wrong_token": "wrong or missing token"},
            "the counts are in the management interface's status; a process of the application "
            f"needs the application's token ({TOKEN_ENV}); if that address is not one of yours, "
            "firewall the port",
        )

    def validateHandshake(self, conn: Any, data: Any) -> Any:  # Pyro5's name
        if self._token is not None:
            given = data.encode() if isinstance(data, str) else b""
            if not hmac.compare_digest(given, self._token):
                try:
                    peer = peer_address(conn.sock.getpeername())
                except (OSError, AttributeError):
                    peer = peer_address(None)
                self.refusals.refused("wrong_token", peer)
                raise Pyro5.errors.SecurityError("handshake refused: wrong or missing token")
        # Past the handshake: the deadline was for strangers; the caller's proxy keeps this
        # connection for its next call, however far away.
        conn.timeout = None
        return "acordcs"


def configure_server(handshake_timeout: float, max_connections: int) -> None:
    """Pyro5's process-wide server settings: the handshake deadline and the worker pool size."""
    if not handshake_timeout > 0:
        raise ConfigurationError(f"handshake_timeout must be > 0 seconds, not {handshake_timeout}")
    if max_connections < 1:
        raise ConfigurationError(f"max_connections must be >= 1, not {max_connections}")
    cfg = Pyro5.api.config
    cfg.SERVERTYPE = "thread"
    cfg.COMMTIMEOUT = float(handshake_timeout)
    cfg.THREADPOOL_SIZE = max(int(max_connections), cfg.THREADPOOL_SIZE_MIN)
