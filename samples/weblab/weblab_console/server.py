"""The WebLab's panel on the console of any application (:mod:`acordcs.console`): registered in
the console's panel table (:func:`acordcs.console.panels.panel_table`, as ``extra``: the WebLab's
sample is not an installed package), with its static files (``panel_static/``), its commands
(:mod:`weblab_console.commands`), the cameras' frames as binary channels and manual driving paced
at :data:`DRIVES_PER_SECOND`.

:func:`create_app` serves the console's page with this panel over a panel session: the
experiment run in this process (:class:`weblab_console.session.ConsoleSession`, watched through
:mod:`.in_process`) or the two-process application (:class:`weblab_console.attached.AttachedPanel`
on :func:`live_console`). The page, the server's promises (Host and Origin checks, headers,
viewers' slots, strikes, refusals counted) and the architecture, context, policies, events and
hands are the console's.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable
from importlib import resources
from typing import Any

from starlette.applications import Starlette

from acordcs.console import web_app
from acordcs.console.attaching import Application
from acordcs.console.fanout import ConsoleHub
from acordcs.console.live_session import LiveSession
from acordcs.console.panels import ConsolePanel, PanelContext, panel_table, panels_for
from acordcs.console.site_guard import LOOPBACK_NAMES
from acordcs.console.web_app import STRIKES, quiet_uvicorn
from acordcs.runtime.refusals import Refusals
from weblab_console.attached import PROFILE, AttachedPanel
from weblab_console.commands import parse
from weblab_console.in_process import InProcess, weblab_descriptor
from weblab_console.showing import PANEL

__all__ = ["STRIKES", "console_refusals", "create_app", "live_console", "quiet_uvicorn"]

FRAME_CHANNELS = {"frame:onboard": 1, "frame:panoramic": 2}
"""Binary channels: the byte that starts each message."""

DRIVES_PER_SECOND = 30
COMMANDS = frozenset(("start", "stop", "drive", "release"))


def weblab_panel(attach: Callable[[PanelContext], Any], profiles: tuple[str, ...]) -> ConsolePanel:
    """The WebLab's panel, whose sessions ``attach`` makes and whose ``start`` takes
    ``profiles``."""
    return ConsolePanel(
        name=PANEL,
        title="WebLab: cameras, navigation map, teleoperation",
        static=resources.files("weblab_console") / "panel_static",
        applies=lambda d: (
            {"Locomotion", "Vision"}
            <= {component for c in d.containers for component in c.hosted("component")}
        ),
        attach=attach,
        parse=functools.partial(parse, profiles=profiles),
        commands=COMMANDS,
        binary_channels=FRAME_CHANNELS,
        paced={"drive": DRIVES_PER_SECOND},
    )


def _console(
    hub: ConsoleHub, token: str, app: Any, panel: ConsolePanel, **options: Any
) -> LiveSession:
    table = panel_table(extra={PANEL: panel})
    return LiveSession(hub, token, app, panels=panels_for(app.descriptor, table), **options)


def live_console(hub: ConsoleHub, token: str, app: Application) -> LiveSession:
    """The console attached to the two-process application ``app``, with the WebLab's panel."""
    return _console(hub, token, app, weblab_panel(AttachedPanel, (PROFILE,)))


def simulation_console(hub: ConsoleHub, session: Any) -> LiveSession:
    """The console over ``session``, the experiment in this process (or a test's double of it:
    ``profiles``, ``authorize``, the commands), with the WebLab's panel. Who holds the token is
    the session's ``authorize``."""
    panel = weblab_panel(lambda context: session, tuple(session.profiles))
    app = getattr(session, "in_process", None) or InProcess(weblab_descriptor())
    return _console(hub, getattr(session, "token", ""), app, panel, admits=session.authorize)


def console_refusals() -> Refusals:
    """The console's refusals, logged on the 1st, 2nd, 4th, 8th... of each kind only."""
    return web_app.console_refusals(web_app.ConsoleSite(
        "acordcs console", resources.files("acordcs.console") / "static", "acordcs", parse
    ))  # fmt: skip


def create_app(
    hub: ConsoleHub,
    session: Any,
    *,
    allowed_hosts: Iterable[str] = LOOPBACK_NAMES,
    refusals: Refusals | None = None,
) -> Starlette:
    """The console's ASGI application with the WebLab's panel over ``session``: a
    :class:`LiveSession` as it is, else the panel session of :func:`simulation_console`."""
    console = session if isinstance(session, LiveSession) else simulation_console(hub, session)
    return web_app.create_app(
        console.site(),
        hub,
        console,
        allowed_hosts=allowed_hosts,
        refusals=refusals if refusals is not None else console_refusals(),
    )
