"""The console with the WebLab's panel (``session``: its panel session, or the console's
:class:`~acordcs.console.live_session.LiveSession`) served by uvicorn in a background thread of this process (for tests,
benchmark and the screenshot script): ``with serving(hub, session) as url: ...``; leaving the
block stops the server and the session's experiment."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from acordcs.console import in_thread
from acordcs.console.fanout import ConsoleHub
from acordcs.console.in_thread import free_port
from acordcs.console.live_session import LiveSession
from acordcs.console.site_guard import allowed_names
from weblab_console.server import console_refusals, create_app, simulation_console

__all__ = ["free_port", "serving"]


@contextmanager
def serving(
    hub: ConsoleHub, session: Any, *, host: str = "127.0.0.1", port: int = 0
) -> Iterator[str]:
    """The console's base URL (``http://host:port``) while the block runs."""
    refusals = console_refusals()
    console = session if isinstance(session, LiveSession) else simulation_console(hub, session)
    try:
        console.attach()
        app = create_app(hub, console, allowed_hosts=allowed_names(host), refusals=refusals)
        with in_thread.serving(app, refusals, host=host, port=port) as url:
            yield url
    finally:
        console.close()  # and its panel's session: the experiment stops
