"""What the console checks on every request before the application sees it, and the headers it
adds to every response (an ASGI middleware around the Starlette application).

- **Host.** The ``Host`` header must name the console: an address it is bound to, or a name given
  with ``--allow-host``; the loopback names (``127.0.0.1``, ``localhost``, ``::1``) when it is bound
  to loopback. A page whose own name resolves to this machine (DNS rebinding: ``evil.example``
  pointing at 127.0.0.1) sends ``Host: evil.example`` and is refused (HTTP 400 with the reason; a
  WebSocket is closed before it opens, which the browser sees as HTTP 403).
- **Origin.** A WebSocket whose ``Origin`` is not the console's own origin (``http://`` or
  ``https://`` and the ``Host`` the request was sent to) is refused: another site's page (or
  another port's) cannot open the live stream in the user's browser (cross-site WebSocket
  hijacking). Scheme and host compare case-insensitively, as RFC 3986 says they are
  (``http://LOCALHOST:8765`` is ``http://localhost:8765``); the port and the rest compare exactly
  (:func:`same_origin`). A client that sends no ``Origin`` is not a browser, and could send any:
  it is let in (the token still decides what it may do).
- **Refusals** are counted by kind (``host``, ``origin``) with the console's others and logged
  on the 1st, 2nd, 4th, 8th... of each kind only, with the peer's address.
- **Headers.** Every HTTP response carries a Content-Security-Policy that allows only the console's
  own scripts, styles, images (and the ``blob:`` URLs of camera frames) and its own WebSocket,
  ``X-Frame-Options: DENY`` (and ``frame-ancestors 'none'``: no page may frame the console),
  ``Referrer-Policy: no-referrer`` and ``X-Content-Type-Options: nosniff``.
"""

from __future__ import annotations

import ipaddress
from collections.abc import Iterable

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from acordcs.runtime.refusals import Refusals, peer_address

LOOPBACK_NAMES = ("127.0.0.1", "localhost", "::1")


def is_loopback(host: str) -> bool:
    """Whether ``host`` (an address or a name) is this machine's loopback interface only."""
    if host.strip("[]").lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def allowed_names(host: str, extra: Iterable[str] = ()) -> frozenset[str]:
    """The ``Host`` names a console bound to ``host`` answers to: ``host`` itself (unless it is a
    wildcard address), the loopback names when it listens on loopback or everywhere, and ``extra``
    (``--allow-host``; a port given there is ignored: the check is on the name)."""
    names = {host_name(e) for e in extra}
    bare = host.strip("[]").lower()
    if bare not in ("0.0.0.0", "::", ""):
        names.add(bare)
    if is_loopback(bare) or bare in ("0.0.0.0", "::", ""):
        names.update(LOOPBACK_NAMES)
    return frozenset(names)


def host_name(host_header: str) -> str:
    """The name of a ``Host`` value: lower case, without its port, IPv6 brackets removed."""
    value = host_header.strip().lower()
    if value.startswith("["):
        return value[1 : value.find("]")] if "]" in value else value
    return value.rsplit(":", 1)[0] if value.count(":") == 1 else value


def same_origin(origin: str, host_header: str) -> bool:
    """Whether ``origin`` (an ``Origin`` header) is ``http://`` or ``https://`` and the
    ``Host`` a request was sent to: scheme and host case-insensitively (RFC 3986, 3.1 and 3.2.2),
    the port, and anything else, exactly."""
    scheme, sep, authority = origin.partition("://")
    if not sep or scheme.lower() not in ("http", "https"):
        return False
    return _folded(authority) == _folded(host_header)


def _folded(authority: str) -> str:
    """``host[:port]`` with the host in lower case, the port as it is."""
    if authority.startswith("["):  # an IPv6 address: [::1]:8765
        end = authority.find("]")
        return authority if end < 0 else authority[: end + 1].lower() + authority[end + 1 :]
    host, colon, port = authority.rpartition(":")
    return host.lower() + colon + port if colon else authority.lower()


def security_headers(host: str | None) -> list[tuple[bytes, bytes]]:
    """The headers every response carries; ``host``: the request's (checked) ``Host``, None for a
    refusal (which connects nowhere)."""
    connect = f"'self' ws://{host} wss://{host}" if host else "'none'"
    policy = (
        "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' blob:; "
        f"connect-src {connect}; base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
    )
    return [
        (b"content-security-policy", policy.encode("latin-1")),
        (b"x-frame-options", b"DENY"),
        (b"referrer-policy", b"no-referrer"),
        (b"x-content-type-options", b"nosniff"),
    ]


class SiteGuard:
    """The checks and headers of the module doc around ``app``."""

    def __init__(self, app: ASGIApp, allowed_hosts: Iterable[str], refusals: Refusals) -> None:
        self.app = app
        self.allowed = frozenset(allowed_hosts)
        self.refusals = refusals

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        headers = {k.decode("latin-1"): v.decode("latin-1") for k, v in scope["headers"]}
        host = headers.get("host", "")
        if host_name(host) not in self.allowed:
            why = (
                f"Host {host[:80]!r} is not a name this console answers to "
                f"({', '.join(sorted(self.allowed))}): refused (a page reaching it under another "
                "name, e.g. by DNS rebinding); start the console with --allow-host NAME to serve "
                "that name"
            )
            await self._refuse(scope, receive, send, why, "host", f"Host {host[:80]!r}")
            return
        origin = headers.get("origin")
        foreign = origin is not None and not same_origin(origin, host)
        if scope["type"] == "websocket" and foreign:
            why = (
                f"a WebSocket from origin {origin!r:.80} is not the console's own "
                f"(http://{host}): refused (another site's page in the viewer's browser)"
            )
            await self._refuse(scope, receive, send, why, "origin", f"Origin {origin!r:.80}")
            return
        if scope["type"] == "websocket":
            await self.app(scope, receive, send)
            return
        extra = security_headers(host)

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []), *extra]}
            await send(message)

        await self.app(scope, receive, send_with_headers)

    async def _refuse(
        self, scope: Scope, receive: Receive, send: Send, why: str, kind: str, sent: str
    ) -> None:
        """Refuse the request (``why``: the answer's text) and count it as ``kind``; ``sent``:
        what it sent that was refused, for the log."""
        what = "a WebSocket" if scope["type"] == "websocket" else "a request"
        self.refusals.refused(kind, peer_address(scope.get("client")), what, sent)
        if scope["type"] == "websocket":
            await receive()  # websocket.connect
            await send({"type": "websocket.close", "code": 1008, "reason": ""})
            return
        body = f"{why}\n".encode()
        await send(
            {
                "type": "http.response.start",
                "status": 400,
                "headers": [
                    (b"content-type", b"text/plain; charset=utf-8"),
                    (b"content-length", str(len(body)).encode()),
                    *security_headers(None),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})
