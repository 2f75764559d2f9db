"""The WebLab console's site on the generic console server (:mod:`acordcs.console.web_app`): its
page (``static/``), its subprotocol ``weblab``, its commands (:mod:`weblab_console.commands`), the
cameras' frames as binary channels, and manual driving paced at :data:`DRIVES_PER_SECOND`.

Camera frames go as binary messages (one byte naming the camera, then the JPEG; both cameras'
pending frames as one message, see :mod:`acordcs.console.web_app`); everything else as JSON.
The server's promises (Host and Origin checks, headers, viewers' slots, strikes, refusals
counted) are the generic console's.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable
from importlib import resources
from typing import Any, Protocol

from starlette.applications import Starlette

from acordcs.console import web_app
from acordcs.console.fanout import ConsoleHub
from acordcs.console.site_guard import LOOPBACK_NAMES
from acordcs.console.web_app import STRIKES, ConsoleSite, quiet_uvicorn
from acordcs.runtime.refusals import Refusals
from weblab_console.commands import parse

__all__ = ["STRIKES", "Session", "console_refusals", "create_app", "quiet_uvicorn"]

FRAME_CHANNELS = {"frame:onboard": 1, "frame:panoramic": 2}
"""Binary channels: the byte that starts each message."""

DRIVES_PER_SECOND = 30


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

    def describe(self) -> dict[str, Any]: ...


def site(profiles: tuple[str, ...]) -> ConsoleSite:
    """The WebLab console's site, whose ``start`` takes ``profiles``."""
    return ConsoleSite(
        name="WebLab console",
        static=resources.files("weblab_console") / "static",
        protocol="weblab",
        parse=functools.partial(parse, profiles=profiles),
        binary_channels=FRAME_CHANNELS,
        paced={"drive": DRIVES_PER_SECOND},
        subject="the experiment",
        logger="weblab.console",
    )


def described(session: Session) -> dict[str, Any]:
    """What a viewer is told first and ``/status`` shows: the session's profiles and mode."""
    return {"profiles": list(session.profiles), "mode": session.mode}


def console_refusals() -> Refusals:
    """The WebLab console's refusals, logged on the 1st, 2nd, 4th, 8th... of each kind only."""
    return web_app.console_refusals(site(()))


def create_app(
    hub: ConsoleHub,
    session: Session,
    *,
    allowed_hosts: Iterable[str] = LOOPBACK_NAMES,
    refusals: Refusals | None = None,
) -> Starlette:
    """The WebLab console's ASGI application over ``hub`` and ``session``."""
    return web_app.create_app(
        site(session.profiles),
        hub,
        session,
        allowed_hosts=allowed_hosts,
        refusals=refusals if refusals is not None else console_refusals(),
    )
