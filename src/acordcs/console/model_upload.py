"""``POST /model``: a changed model sent from the console's page (:meth:`LiveSession.upload
<acordcs.console.live_session.LiveSession.upload>` writes it where the console alone reads and
plans it with ``acordcs-gen update --dry-run``; the page's next ``apply`` applies it).

What it checks, before reading the body: an ``Origin``, when sent, is the console's own; the
console's token comes in the header ``X-Acordcs-Token`` (a page of another site cannot send that
header without a CORS preflight, which the console does not answer); the file's name
(``X-Acordcs-Model-Name``) is a plain name ending in ``.uml``, ``.xmi`` or ``.acord``; then it
reads at most :data:`MAX_MODEL` bytes. Each refusal is counted as the WebSocket's are
(``/status``).
"""

from __future__ import annotations

import asyncio
import re
from typing import Any

from starlette.requests import Request
from starlette.responses import JSONResponse

from acordcs.console.site_guard import same_origin
from acordcs.console.viewer_messages import valid_token
from acordcs.runtime.refusals import Refusals, peer_address

MAX_MODEL = 2 * 1024 * 1024
"""Bytes of a model a viewer may send."""

MODEL_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,99}\.(uml|xmi|acord)\Z")


async def receive(request: Request, session: Any, refused: Refusals) -> JSONResponse:
    """``POST /model``: a changed model from the page (the session's ``upload`` plans it). The
    token comes in the header ``X-Acordcs-Token`` (another site's page cannot send that header
    without a preflight, which is not answered), the file's name in ``X-Acordcs-Model-Name``;
    at most :data:`MAX_MODEL` bytes."""
    peer = peer_address(request.client)
    origin = request.headers.get("origin")
    if origin is not None and not same_origin(origin, request.headers.get("host", "")):
        refused.refused("origin", peer, "a model", f"Origin {origin[:80]!r}")
        return _no(403, "a model from another site's page", "use the console's own page")
    token = request.headers.get("x-acordcs-token", "")
    if not valid_token(token) or not await asyncio.to_thread(_admits, session, token):
        refused.refused("token", peer, "a model")
        return _no(403, "a model needs the console's token", "open the link the console printed")
    name = request.headers.get("x-acordcs-model-name", "")
    if not MODEL_NAME.match(name):
        refused.refused("message", peer, "a model", "its name")
        return _no(400, "the model's file name must end in .uml, .xmi or .acord (letters, "
                   "digits, _ . -, at most 100 characters)", "name the file so")  # fmt: skip
    data = bytearray()
    async for chunk in request.stream():
        data += chunk
        if len(data) > MAX_MODEL:
            refused.refused("message", peer, "a model", "over the size limit")
            return _no(413, f"a model of more than {MAX_MODEL} bytes",
                       "send a smaller model, or update with acordcs-gen update")  # fmt: skip
    try:
        planned = await asyncio.to_thread(session.upload, name, bytes(data))
    except Exception as err:  # the session's refusal: told, not fatal
        refused.refused("failed", peer, "a model", f"{type(err).__name__}: {err}"[:200])
        return _no(409, f"{type(err).__name__}: {err}", "see the console's documentation")
    return JSONResponse(planned)


def _admits(session: Any, token: str) -> bool:
    try:
        return session.authorize(token) is True
    except Exception:
        return False


def _no(status: int, why: str, todo: str) -> JSONResponse:
    return JSONResponse({"type": "refused", "why": why, "todo": todo}, status_code=status)
