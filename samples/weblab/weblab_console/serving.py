"""The WebLab console served by uvicorn in a background thread of this process (for tests,
benchmark and the screenshot script): ``with serving(hub, session) as url: ...``; leaving the
block stops the server and the session's experiment."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from acordcs.console import in_thread
from acordcs.console.fanout import ConsoleHub
from acordcs.console.in_thread import free_port
from acordcs.console.site_guard import allowed_names
from weblab_console.server import Session, console_refusals, create_app

__all__ = ["free_port", "serving"]


@contextmanager
def serving(
    hub: ConsoleHub, session: Session, *, host: str = "127.0.0.1", port: int = 0
) -> Iterator[str]:
    """The console's base URL (``http://host:port``) while the block runs."""
    refusals = console_refusals()
    app = create_app(hub, session, allowed_hosts=allowed_names(host), refusals=refusals)
    try:
        with in_thread.serving(app, refusals, host=host, port=port) as url:
            yield url
    finally:
        # close() also drops the idle application the session keeps for the access service.
        end = getattr(session, "close", None) or getattr(session, "stop", None)
        if end is not None:
            end()
