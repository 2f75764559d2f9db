"""A console's web server: one page and one WebSocket, on Starlette (served by uvicorn), for any
console (:class:`ConsoleSite` says what is its own: its page, its subprotocol, its commands, its
binary channels): the generic console of :mod:`acordcs.console` and the WebLab's.

``GET /`` is the page (``index.html`` of the site's static directory, ES modules and a style sheet,
no build step); ``/ws`` streams what the :class:`~acordcs.console.fanout.ConsoleHub` publishes:
the payloads of the site's binary channels as binary messages (one byte naming the channel, then
the bytes; when several are pending, one message: a 0 byte, then for each a byte naming the
channel, its length in 4 bytes, big-endian, and the bytes), everything else as JSON text: an
object ``{"type", "data"}``, or an array of such objects when several were pending. A viewer sends
commands (read by the site's parser, strictly: :mod:`acordcs.console.viewer_messages`); those
that change what the console drives need the session's token, which the session checks
(``authorize``). The page presents the token when it opens the WebSocket, as the subprotocol
``<protocol>.token.<token>`` beside ``<protocol>`` (a header: never in a URL), so the server knows
at once whether the viewer holds it.

What it promises, and its limits:

- every request passes :class:`~acordcs.console.site_guard.SiteGuard` first: its ``Host`` must
  name the console, a WebSocket's ``Origin`` must be the console's own; responses carry a
  Content-Security-Policy, ``X-Frame-Options: DENY`` and ``Referrer-Policy: no-referrer``;
- it authenticates nothing but the token, and trusts no viewer message: each is parsed strictly, at
  most 4 KB (uvicorn refuses frames over 64 KB before we see them);
- at most ``max_viewers`` connections holding the token and ``max_watchers`` without it (the hub's
  caps, kept apart: connections without the token never take a token holder's place); one more is
  told so and closed (code 1013, try again later); 20 refused messages close a viewer (1008);
  a paced command (the site's ``paced``: the WebLab's ``drive``) is taken at most so many times a
  second per viewer;
- a message the console fails to handle (whatever it raised) is refused like an invalid one: a
  strike, an answer saying so, never a traceback in the log nor a dropped connection;
- refusals are counted by kind (:data:`REFUSED`; ``GET /status`` gives the counts) and logged on
  the 1st, 2nd, 4th, 8th... of each kind only, with the peer's address
  (:class:`acordcs.runtime.refusals.Refusals`): a peer refused again and again cannot grow the
  log at will;
- a viewer never slows what the console shows: the publisher only stores into the viewer's
  mailbox (see the hub), and each viewer's sender awaits its own socket; the publishing thread
  wakes the server's event loop once for every viewer with something new, not once per viewer
  (:class:`_Waker`), and a viewer's sender takes what is pending at most
  :data:`SENDS_PER_SECOND` times a second, so that what was published meanwhile goes together;
- the session failing in a command is a message to the page, never a crash.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from importlib.resources.abc import Traversable
from typing import Any, Protocol

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from acordcs.console import model_upload
from acordcs.console.fanout import ConsoleHub
from acordcs.console.site_guard import LOOPBACK_NAMES, SiteGuard
from acordcs.console.viewer_messages import Command, CommandError, valid_token
from acordcs.runtime.refusals import Refusals, peer_address

BUNDLE = 0
"""The byte that starts a binary message holding several payloads of binary channels."""

STRIKES = 20
SENDS_PER_SECOND = 30
"""How often a viewer's sender takes what is pending, at most (the WebLab's cameras send at most
15 frames a second)."""


@dataclass(frozen=True)
class ConsoleSite:
    """What makes a console its own: ``name`` (in its log and refusals), its ``static`` directory
    (``index.html`` and what it loads), its WebSocket subprotocol ``protocol`` (the token comes as
    ``<protocol>.token.<token>``), ``parse`` (a viewer message as a :class:`Command`, or
    :class:`CommandError`: ``ping`` and ``auth`` are answered here, every other command is the
    session's method of its name, called with its arguments, and needs the token),
    ``binary_channels`` (channel -> the byte that starts its messages: payloads sent as bytes),
    ``paced`` (command -> how many a viewer may send a second: more are dropped quietly),
    ``subject`` (what a command changes, in a refusal: ``the application``), ``logger``: the name
    of its log."""

    name: str
    static: Traversable
    protocol: str
    parse: Callable[[str | bytes], Command]
    binary_channels: Mapping[str, int] = field(default_factory=dict)
    paced: Mapping[str, int] = field(default_factory=dict)
    subject: str = "the application"
    logger: str = "acordcs.console"
    panels: Mapping[str, Traversable] = field(default_factory=dict)
    """Panel name -> its static directory, served under ``/panels/<name>/``
    (:mod:`acordcs.console.panels`)."""

    @property
    def token_protocol(self) -> str:
        return f"{self.protocol}.token."

    @property
    def log(self) -> logging.Logger:
        return logging.getLogger(self.logger)


REFUSED = {
    "host": "sent to a name this console does not answer to (a page reaching it under another "
    "name, e.g. by DNS rebinding; --allow-host NAME serves a name)",
    "origin": "a WebSocket from another site's page (cross-site WebSocket hijacking)",
    "token": "a token the access service does not know",
    "full": "the console has its maximum of viewers of that kind",
    "message": "not a valid command, or a command that needs the session's token",
    "closed": f"{STRIKES} refused messages: the connection was closed (1008)",
    "fault": "handling it raised an exception (refused, as an invalid message is)",
    "failed": "what the console drives did not carry the command out",
    "invalid": "not an HTTP or WebSocket request the server could read (uvicorn does not say "
    "whose)",
}
"""What the console refuses, by kind: the counts of ``GET /status`` (``refused``)."""


WATCHING_NEEDS_TOKEN = {
    "type": "refused",
    "why": "this console shows the application only to viewers holding its token (a console "
    "started with no viewer without the token: --watchers 0, the default for an application "
    "started with a token)",
    "todo": "open the console with the link the console printed (it holds the token)",
}
"""What a viewer without the token is told when the console takes none (``max_watchers`` 0)."""


UVICORN_NOISE = frozenset(
    (
        "Invalid HTTP request received.",
        "Unsupported upgrade request.",
        "Exceeded concurrency limit.",
        "Invalid UTF-8 sequence received from client.",
    )
)
"""uvicorn's warnings about one request it could not take: one line per request (and a
traceback for the last), which any client could repeat at will."""


class _QuietUvicorn(logging.Filter):
    """Takes :data:`UVICORN_NOISE` out of uvicorn's log, counting each as the console's refusal
    ``invalid`` (logged on the 1st, 2nd, 4th, 8th... only)."""

    def __init__(self, refusals: Refusals) -> None:
        super().__init__()
        self.refusals = refusals

    def filter(self, record: logging.LogRecord) -> bool:
        if record.msg in UVICORN_NOISE:
            self.refusals.refused("invalid", peer_address(None), "a request", str(record.msg))
            return False
        return True


@contextlib.contextmanager
def quiet_uvicorn(refusals: Refusals) -> Iterator[None]:
    """While the block runs, uvicorn's per-request warnings (:data:`UVICORN_NOISE`) are counted
    in ``refusals`` instead of logged each time (uvicorn's logger is the process's: one console
    server at a time)."""
    logger = logging.getLogger("uvicorn.error")
    quiet = _QuietUvicorn(refusals)
    logger.addFilter(quiet)
    try:
        yield
    finally:
        logger.removeFilter(quiet)


def console_refusals(site: ConsoleSite) -> Refusals:
    """The console's refusals, logged on the 1st, 2nd, 4th, 8th... of each kind only."""
    return Refusals(
        site.log,
        site.name,
        REFUSED,
        "the counts are in the console's /status; a viewer needs the link the console printed "
        "(it holds the token); see docs/console.md, Security model",
    )


class Session(Protocol):
    """What a console drives: ``authorize`` says whether a token is the session's; ``describe``
    what a viewer is told first (in ``hello``) and ``/status`` shows; every command of the site
    but ``ping`` and ``auth`` is a method of the session's (a result that is not None is sent
    back with ``done``)."""

    def authorize(self, token: str) -> bool: ...

    def describe(self) -> dict[str, Any]: ...


class _Viewer:
    """One connection's state: its peer's address, whether it holds the token, its strikes and
    drive budget, and where its refusals are counted."""

    def __init__(self, peer: str, refusals: Refusals) -> None:
        self.peer = peer
        self.refusals = refusals
        self.authorized = False
        self.strikes = 0
        self.windows: dict[str, tuple[float, int]] = {}

    def within(self, command: str, per_second: int) -> bool:
        """Whether one more ``command`` is within ``per_second`` this second."""
        now = time.monotonic()
        start, count = self.windows.get(command, (0.0, 0))
        if now - start >= 1.0:
            start, count = now, 0
        self.windows[command] = (start, count + 1)
        return count + 1 <= per_second


def create_app(
    site: ConsoleSite,
    hub: ConsoleHub,
    session: Session,
    *,
    allowed_hosts: Iterable[str] = LOOPBACK_NAMES,
    refusals: Refusals | None = None,
) -> Starlette:
    """The console ``site``'s ASGI application over ``hub`` and ``session``; ``allowed_hosts``:
    the names requests may be sent to (:func:`acordcs.console.site_guard.allowed_names`);
    ``refusals``: where its refusals are counted (default: :func:`console_refusals`)."""
    refused = refusals if refusals is not None else console_refusals(site)
    static = site.static

    async def page(request) -> FileResponse:
        return FileResponse(str(static / "index.html"), media_type="text/html")

    async def status(request) -> JSONResponse:
        return JSONResponse({**session.describe(), **hub.stats(), "refused": refused.counts()})

    async def model(request: Request) -> JSONResponse:
        return await model_upload.receive(request, session, refused)

    encode = _Encoded(site.binary_channels)  # shared by the senders, all on the server's loop
    waker = _Waker()

    async def socket(websocket: WebSocket) -> None:
        offered = [
            p.strip() for p in websocket.headers.get("sec-websocket-protocol", "").split(",")
        ]
        prefix = site.token_protocol
        token = next((p[len(prefix) :] for p in offered if p.startswith(prefix)), "")
        viewer = _Viewer(peer_address(websocket.client), refused)
        if valid_token(token):
            viewer.authorized = await asyncio.to_thread(_call, session.authorize, token, viewer)
        await websocket.accept(subprotocol=site.protocol if site.protocol in offered else None)
        waker.loop = asyncio.get_running_loop()
        pending = asyncio.Event()
        if not viewer.authorized and hub.max_watchers == 0:
            refused.refused("token", viewer.peer, "a viewer without the token")
            await websocket.send_text(json.dumps(WATCHING_NEEDS_TOKEN))
            await websocket.close(code=1008)
            return
        joined = hub.join(lambda: waker.wake(pending), holder=viewer.authorized)
        if joined is None:
            refused.refused("full", viewer.peer)
            kind = (
                f"{hub.max_viewers} viewers holding the token"
                if viewer.authorized
                else f"{hub.max_watchers} viewers without the token (watching only)"
            )
            await websocket.send_text(
                json.dumps(
                    {
                        "type": "refused",
                        "why": f"the console has its maximum of {kind}",
                        "todo": "close another console tab, or try again later",
                    }
                )
            )
            await websocket.close(code=1013)
            return
        viewer_id, box = joined
        pending.set()  # the current state first
        hello = {"type": "hello", **session.describe()}
        await websocket.send_text(json.dumps(hello))
        if token:
            await websocket.send_text(json.dumps(_token_reply(viewer)))
        sender = asyncio.create_task(_send(websocket, hub, box, pending, encode))
        try:
            await _receive(websocket, site, session, viewer)
        finally:
            hub.leave(viewer_id)
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await sender

    return Starlette(
        routes=[
            Route("/", page),
            Route("/status", status),
            *([Route("/model", model, methods=["POST"])] if hasattr(session, "upload") else []),
            WebSocketRoute("/ws", socket),
            Mount("/static", StaticFiles(directory=str(static)), name="static"),
            *(
                Mount(f"/panels/{name}", StaticFiles(directory=str(files)))
                for name, files in site.panels.items()
            ),
        ],
        middleware=[
            Middleware(SiteGuard, allowed_hosts=frozenset(allowed_hosts), refusals=refused)
        ],
    )


class _Waker:
    """Wakes viewers' senders from the publishing thread with one call into the event loop for all
    of them: the first wake since the loop last ran schedules it, the next ones only add their
    viewer (a call into the loop per viewer and publish was a system call each, on the
    publisher's thread)."""

    def __init__(self) -> None:
        self.loop: asyncio.AbstractEventLoop | None = None
        self._lock = threading.Lock()
        self._events: list[asyncio.Event] = []
        self._scheduled = False

    def wake(self, event: asyncio.Event) -> None:  # any thread
        with self._lock:
            self._events.append(event)
            if self._scheduled or self.loop is None:
                return
            self._scheduled = True
        with contextlib.suppress(RuntimeError):  # the loop is closing
            self.loop.call_soon_threadsafe(self._run)

    def _run(self) -> None:  # on the loop
        with self._lock:
            events, self._events, self._scheduled = self._events, [], False
        for event in events:
            event.set()


class _Encoded:
    """Each payload encoded once for all viewers (by identity: every mailbox holds the same object;
    the object is kept with its encoding, so its id cannot be reused while cached)."""

    def __init__(self, binary_channels: Mapping[str, int], keep: int = 256) -> None:
        self.binary_channels = binary_channels
        self.keep = keep
        self.cache: dict[int, tuple[Any, str | bytes]] = {}
        self.bundles: dict[tuple[int, ...], tuple[list[bytes], bytes]] = {}

    def __call__(self, channel: str, payload: Any) -> str | bytes:
        found = self.cache.get(id(payload))
        if found is not None and found[0] is payload:
            return found[1]
        tag = self.binary_channels.get(channel)
        if tag is not None:
            encoded: str | bytes = bytes([tag]) + payload
        else:
            encoded = json.dumps({"type": channel, "data": payload})
        self._keep(payload, encoded)
        return encoded

    def bundle(self, frames: list[bytes]) -> bytes:
        """Several encoded binary payloads (frames) as one message (see the module docstring); the same frames
        (these very objects: each viewer gets the same encodings) give the same message."""
        key = tuple(id(f) for f in frames)
        found = self.bundles.get(key)
        if found is not None and all(a is b for a, b in zip(found[0], frames, strict=True)):
            return found[1]
        encoded = bytes([BUNDLE]) + b"".join(
            f[:1] + len(f[1:]).to_bytes(4, "big") + f[1:] for f in frames
        )
        if len(self.bundles) >= self.keep:
            self.bundles.pop(next(iter(self.bundles)))
        self.bundles[key] = (list(frames), encoded)
        return encoded

    def _keep(self, payload: Any, encoded: str | bytes) -> None:
        if len(self.cache) >= self.keep:
            self.cache.pop(next(iter(self.cache)))
        self.cache[id(payload)] = (payload, encoded)


async def _send(
    websocket: WebSocket, hub: ConsoleHub, box, pending: asyncio.Event, encode: _Encoded
) -> None:
    loop = asyncio.get_running_loop()
    gap = 1.0 / SENDS_PER_SECOND
    last = 0.0
    while True:
        await pending.wait()
        wait = last + gap - loop.time()
        if wait > 0:  # what is published meanwhile goes with it
            await asyncio.sleep(wait)
        pending.clear()
        last = loop.time()
        latest, events = hub.take(box)
        texts: list[str] = []
        frames: list[bytes] = []
        for channel, payload in latest.items():
            message = encode(channel, payload)
            if isinstance(message, bytes):
                frames.append(message)
            else:
                texts.append(message)
        if len(frames) == 1:
            await websocket.send_bytes(frames[0])
        elif frames:  # one message: a send costs more than the bytes it carries
            await websocket.send_bytes(encode.bundle(frames))
        texts.extend(encode("event", event) for event in events)  # type: ignore[misc]
        # What is pending goes as one JSON array (the page reads an array as its messages in
        # order): one WebSocket message per wake, not one per payload.
        if len(texts) == 1:
            await websocket.send_text(texts[0])
        elif texts:
            await websocket.send_text("[" + ",".join(texts) + "]")


async def _receive(
    websocket: WebSocket, site: ConsoleSite, session: Session, viewer: _Viewer
) -> None:
    while True:
        try:
            message = await websocket.receive()
        except (WebSocketDisconnect, RuntimeError):
            return
        if message["type"] == "websocket.disconnect":
            return
        raw = message.get("text") if message.get("text") is not None else message.get("bytes")
        # In a worker thread: a command may wait for what the console drives (a call, an
        # update, the access service), and the other viewers' senders must go on meanwhile.
        reply = await asyncio.to_thread(_handle, raw or "", site, session, viewer)
        if reply is not None:
            try:
                await websocket.send_text(json.dumps(reply))
            except (WebSocketDisconnect, RuntimeError):
                return
        if viewer.strikes >= STRIKES:
            viewer.refusals.refused("closed", viewer.peer, "a viewer")
            with contextlib.suppress(Exception):
                await websocket.close(code=1008)
            return


def _handle(
    raw: str | bytes, site: ConsoleSite, session: Session, viewer: _Viewer
) -> dict[str, Any] | None:
    """The answer to one viewer message (None: none). Whatever handling it raises is a refusal
    of the message, counted as a strike and answered, never an escape (an escape would close the
    connection, 1006, and log a traceback)."""
    try:
        return _command(raw, site, session, viewer)
    except Exception as err:
        viewer.strikes += 1
        viewer.refusals.refused("fault", viewer.peer, "a message", type(err).__name__)
        return {
            "type": "refused",
            "why": f"the console could not handle this message ({type(err).__name__})",
            "todo": "send one of the console's commands (see its command list)",
        }


def _command(
    raw: str | bytes, site: ConsoleSite, session: Session, viewer: _Viewer
) -> dict[str, Any] | None:
    try:
        command = site.parse(raw)
    except CommandError as err:
        viewer.strikes += 1
        viewer.refusals.refused("message", viewer.peer, "a message")
        return {"type": "refused", "why": str(err), "todo": "see the console's command list"}
    if command.name == "ping":
        return {"type": "pong"}
    if command.name == "auth":
        viewer.authorized = _call(session.authorize, command.args["token"], viewer)
        return _token_reply(viewer)
    if not viewer.authorized:
        viewer.strikes += 1
        viewer.refusals.refused("message", viewer.peer, f"'{command.name}'")
        return {
            "type": "refused",
            "why": f"'{command.name}' changes {site.subject} and needs the session's token",
            "todo": "open the console with the link the console printed (it holds the token)",
        }
    pace = site.paced.get(command.name)
    if pace is not None and not viewer.within(command.name, pace):
        return None  # over the rate: dropped quietly, the next one carries the newest values
    handler = getattr(session, "handler", None)  # a session with panels finds their commands
    action: Callable[..., Any] = (
        handler(command.name) if handler is not None else getattr(session, command.name)
    )
    try:
        result = action(**command.args)
    except Exception as err:  # the session's refusal or failure: told, not fatal
        why = f"{type(err).__name__}: {err}"
        viewer.refusals.refused("failed", viewer.peer, f"'{command.name}'", why[:200])
        return {"type": "error", "cmd": command.name, "why": why, **command.echo}
    done = {"type": "done", "cmd": command.name, **command.echo}
    return done if result is None else {**done, "result": result}


def _token_reply(viewer: _Viewer) -> dict[str, Any]:
    """What a viewer is told after presenting a token (a wrong one is a strike)."""
    if viewer.authorized:
        return {"type": "authorized"}
    viewer.strikes += 1
    viewer.refusals.refused("token", viewer.peer, "a token")
    return {
        "type": "refused",
        "why": "the access service does not know this token",
        "todo": "open the console with the link the console printed (it holds the token)",
    }


def _call(fn: Callable[[str], bool], token: str, viewer: _Viewer) -> bool:
    """Whether the access service ``fn`` admits ``token``; one that fails refuses (counted, and
    logged as a fault on the 1st, 2nd, 4th... time: a viewer sending tokens it cannot read must
    not grow the log)."""
    try:
        return fn(token) is True
    except Exception as err:  # its text may quote the token: the log gets its kind only
        viewer.refusals.refused("fault", viewer.peer, "a token", type(err).__name__)
        return False
