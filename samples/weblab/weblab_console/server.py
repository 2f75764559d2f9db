"""The console's web server: one page and one WebSocket, on Starlette (served by uvicorn).

``GET /`` is the page (``static/index.html``, an ES module and a style sheet, no build step);
``/ws`` streams what the :class:`~weblab_console.hub.ConsoleHub` publishes: camera frames as binary
messages (one byte naming the camera, then the JPEG; when frames of both cameras are pending, one
message: a 0 byte, then for each a byte naming the camera, its length in 4 bytes, big-endian, and
the JPEG), everything else as JSON text: an object ``{"type", "data"}``, or an array of such
objects when several were pending. A viewer sends
commands (:mod:`weblab_console.commands`); those that change the experiment need the session's token,
which the application's access service checks (:class:`Session.authorize`). The page presents the
token when it opens the WebSocket, as the subprotocol ``weblab.token.<token>`` beside ``weblab``
(a header: never in a URL), so the server knows at once whether the viewer holds it.

What it promises, and its limits:

- every request passes :class:`~weblab_console.guard.SiteGuard` first: its ``Host`` must name the
  console, a WebSocket's ``Origin`` must be the console's own; responses carry a
  Content-Security-Policy, ``X-Frame-Options: DENY`` and ``Referrer-Policy: no-referrer``;
- it authenticates nothing but the token, and trusts no viewer message: each is parsed strictly, at
  most 4 KB (uvicorn refuses frames over 64 KB before we see them);
- at most ``max_viewers`` connections holding the token and ``max_watchers`` without it (the hub's
  caps, kept apart: connections without the token never take a token holder's place); one more is
  told so and closed (code 1013, try again later); 20 refused messages close a viewer (1008);
  manual driving is taken at most 30 times a second per viewer;
- a message the console fails to handle (whatever it raised) is refused like an invalid one: a
  strike, an answer saying so, never a traceback in the log nor a dropped connection;
- refusals are counted by kind (:data:`REFUSED`; ``GET /status`` gives the counts) and logged on
  the 1st, 2nd, 4th, 8th... of each kind only, with the peer's address
  (:class:`acordcs.runtime.refusals.Refusals`): a peer refused again and again cannot grow the
  log at will;
- a viewer never slows the experiment: the experiment only stores into the viewer's mailbox
  (see the hub), and each viewer's sender awaits its own socket; the experiment's thread wakes the
  server's event loop once for every viewer with something new, not once per viewer
  (:class:`_Waker`), and a viewer's sender takes what is pending at most :data:`SENDS_PER_SECOND`
  times a second, so that what was published meanwhile goes together;
- the experiment stopping, or raising in a command, is a message to the page, never a crash.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from importlib import resources
from typing import Any, Protocol

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.responses import FileResponse, JSONResponse
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from acordcs.runtime.refusals import Refusals, peer_address
from weblab_console.commands import CommandError, parse, valid_token
from weblab_console.guard import LOOPBACK_NAMES, SiteGuard
from weblab_console.hub import ConsoleHub

log = logging.getLogger("weblab.console")

STATIC = resources.files("weblab_console") / "static"
FRAME_CHANNELS = {"frame:onboard": 1, "frame:panoramic": 2}
"""Binary channels: the byte that starts each message."""
BUNDLE = 0
"""The byte that starts a binary message holding several frames."""

STRIKES = 20
DRIVES_PER_SECOND = 30
SENDS_PER_SECOND = 30
"""How often a viewer's sender takes what is pending, at most (cameras send at most 15 frames a
second)."""
PROTOCOL = "weblab"
TOKEN_PROTOCOL = "weblab.token."
"""The subprotocol that carries the session's token when the page opens the WebSocket."""

REFUSED = {
    "host": "sent to a name this console does not answer to (a page reaching it under another "
    "name, e.g. by DNS rebinding; --allow-host NAME serves a name)",
    "origin": "a WebSocket from another site's page (cross-site WebSocket hijacking)",
    "token": "a token the access service does not know",
    "full": "the console has its maximum of viewers of that kind",
    "message": "not a valid command, or a command that needs the session's token",
    "closed": f"{STRIKES} refused messages: the connection was closed (1008)",
    "fault": "handling it raised an exception (refused, as an invalid message is)",
    "failed": "the experiment did not carry the command out",
    "invalid": "not an HTTP or WebSocket request the server could read (uvicorn does not say "
    "whose)",
}
"""What the console refuses, by kind: the counts of ``GET /status`` (``refused``)."""


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


def console_refusals() -> Refusals:
    """The console's refusals, logged on the 1st, 2nd, 4th, 8th... of each kind only."""
    return Refusals(
        log,
        "WebLab console",
        REFUSED,
        "the counts are in the console's /status; a viewer needs the link the console printed "
        "(it holds the token); see docs/console.md, Security model",
    )


class Session(Protocol):
    """What the console drives: the experiment it runs (``mode`` ``simulation``), or the
    application it is attached to (``attached``)."""

    profiles: tuple[str, ...]
    mode: str

    def authorize(self, token: str) -> bool: ...

    def start(self, profile: str, seed: int) -> None: ...

    def stop(self) -> None: ...

    def drive(self, speed: float, turn: float) -> None: ...

    def release(self) -> None: ...


class _Viewer:
    """One connection's state: its peer's address, whether it holds the token, its strikes and
    drive budget, and where its refusals are counted."""

    def __init__(self, peer: str, refusals: Refusals) -> None:
        self.peer = peer
        self.refusals = refusals
        self.authorized = False
        self.strikes = 0
        self.window = 0.0
        self.drives = 0

    def may_drive(self) -> bool:
        now = time.monotonic()
        if now - self.window >= 1.0:
            self.window, self.drives = now, 0
        self.drives += 1
        return self.drives <= DRIVES_PER_SECOND


def create_app(
    hub: ConsoleHub,
    session: Session,
    *,
    allowed_hosts: Iterable[str] = LOOPBACK_NAMES,
    refusals: Refusals | None = None,
) -> Starlette:
    """The console's ASGI application over ``hub`` and ``session``; ``allowed_hosts``: the names
    requests may be sent to (:func:`weblab_console.guard.allowed_names`); ``refusals``: where
    its refusals are counted (default: :func:`console_refusals`)."""
    refused = refusals if refusals is not None else console_refusals()

    async def page(request) -> FileResponse:
        return FileResponse(str(STATIC / "index.html"), media_type="text/html")

    async def status(request) -> JSONResponse:
        return JSONResponse(
            {
                "profiles": list(session.profiles),
                "mode": session.mode,
                **hub.stats(),
                "refused": refused.counts(),
            }
        )

    encode = _Encoded()  # shared by the viewers' senders, all on the server's event loop
    waker = _Waker()

    async def socket(websocket: WebSocket) -> None:
        offered = [
            p.strip() for p in websocket.headers.get("sec-websocket-protocol", "").split(",")
        ]
        token = next(
            (p[len(TOKEN_PROTOCOL) :] for p in offered if p.startswith(TOKEN_PROTOCOL)), ""
        )
        viewer = _Viewer(peer_address(websocket.client), refused)
        if valid_token(token):
            viewer.authorized = await asyncio.to_thread(_call, session.authorize, token, viewer)
        await websocket.accept(subprotocol=PROTOCOL if PROTOCOL in offered else None)
        waker.loop = asyncio.get_running_loop()
        pending = asyncio.Event()
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
        hello = {"type": "hello", "profiles": list(session.profiles), "mode": session.mode}
        await websocket.send_text(json.dumps(hello))
        if token:
            await websocket.send_text(json.dumps(_token_reply(viewer)))
        sender = asyncio.create_task(_send(websocket, hub, box, pending, encode))
        try:
            await _receive(websocket, session, viewer)
        finally:
            hub.leave(viewer_id)
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await sender

    return Starlette(
        routes=[
            Route("/", page),
            Route("/status", status),
            WebSocketRoute("/ws", socket),
            Mount("/static", StaticFiles(directory=str(STATIC)), name="static"),
        ],
        middleware=[
            Middleware(SiteGuard, allowed_hosts=frozenset(allowed_hosts), refusals=refused)
        ],
    )


class _Waker:
    """Wakes viewers' senders from the publishing thread with one call into the event loop for all
    of them: the first wake since the loop last ran schedules it, the next ones only add their
    viewer (a call into the loop per viewer and publish was a system call each, on the
    experiment's thread)."""

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

    def __init__(self, keep: int = 256) -> None:
        self.keep = keep
        self.cache: dict[int, tuple[Any, str | bytes]] = {}
        self.bundles: dict[tuple[int, ...], tuple[list[bytes], bytes]] = {}

    def __call__(self, channel: str, payload: Any) -> str | bytes:
        found = self.cache.get(id(payload))
        if found is not None and found[0] is payload:
            return found[1]
        tag = FRAME_CHANNELS.get(channel)
        if tag is not None:
            encoded: str | bytes = bytes([tag]) + payload
        else:
            encoded = json.dumps({"type": channel, "data": payload})
        self._keep(payload, encoded)
        return encoded

    def bundle(self, frames: list[bytes]) -> bytes:
        """Several encoded frames as one message (see the module docstring); the same frames
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


async def _receive(websocket: WebSocket, session: Session, viewer: _Viewer) -> None:
    while True:
        try:
            message = await websocket.receive()
        except (WebSocketDisconnect, RuntimeError):
            return
        if message["type"] == "websocket.disconnect":
            return
        raw = message.get("text") if message.get("text") is not None else message.get("bytes")
        # In a worker thread: a command may wait for the experiment (start, stop, the access
        # service), and the other viewers' senders must go on meanwhile.
        reply = await asyncio.to_thread(_handle, raw or "", session, viewer)
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


def _handle(raw: str | bytes, session: Session, viewer: _Viewer) -> dict[str, Any] | None:
    """The answer to one viewer message (None: none). Whatever handling it raises is a refusal
    of the message, counted as a strike and answered, never an escape (an escape would close the
    connection, 1006, and log a traceback)."""
    try:
        return _command(raw, session, viewer)
    except Exception as err:
        viewer.strikes += 1
        viewer.refusals.refused("fault", viewer.peer, "a message", type(err).__name__)
        return {
            "type": "refused",
            "why": f"the console could not handle this message ({type(err).__name__})",
            "todo": "send one of the console's commands (see its command list)",
        }


def _command(raw: str | bytes, session: Session, viewer: _Viewer) -> dict[str, Any] | None:
    try:
        command = parse(raw, session.profiles)
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
            "why": f"'{command.name}' changes the experiment and needs the session's token",
            "todo": "open the console with the link the experiment printed (it holds the token)",
        }
    if command.name == "drive" and not viewer.may_drive():
        return None  # over the rate: dropped quietly, the next tick carries the newest values
    action: Callable[..., Any] = getattr(session, command.name)
    try:
        action(**command.args)
    except Exception as err:  # the experiment's refusal or failure: told, not fatal
        why = f"{type(err).__name__}: {err}"
        viewer.refusals.refused("failed", viewer.peer, f"'{command.name}'", why[:200])
        return {"type": "error", "cmd": command.name, "why": why}
    return {"type": "done", "cmd": command.name}


def _token_reply(viewer: _Viewer) -> dict[str, Any]:
    """What a viewer is told after presenting a token (a wrong one is a strike)."""
    if viewer.authorized:
        return {"type": "authorized"}
    viewer.strikes += 1
    viewer.refusals.refused("token", viewer.peer, "a token")
    return {
        "type": "refused",
        "why": "the access service does not know this token",
        "todo": "open the console with the link the experiment printed (it holds the token)",
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
