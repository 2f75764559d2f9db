"""The console of a single-process run, served beside the container by its launcher
(``python -m <package>.<Container> --clock real --console PORT``): the same page and session as
``acordcs-gen console``, attached to this process's own container over loopback (its observer
and management interfaces, as another process would reach them: one implementation), watching
that container only. Its link is printed once it listens; it stops with the container."""

from __future__ import annotations

import contextlib
import secrets
from collections.abc import Callable

from acordcs.console.attaching import Application, Place
from acordcs.console.fanout import ConsoleHub
from acordcs.console.in_thread import serving
from acordcs.console.live_session import LiveSession
from acordcs.console.site_guard import allowed_names, is_loopback
from acordcs.console.web_app import console_refusals, create_app
from acordcs.descriptor import Application as AppDescriptor

HOST = "127.0.0.1"


def serve_beside(
    descriptor: AppDescriptor,
    container: str,
    served: tuple[str, int],
    token: str | None,
    port: int,
    say: Callable[[str], None],
) -> Callable[[], None]:
    """Serve the console of ``container`` (of ``descriptor``, served at ``served``: host and
    port, with the application's ``token``) on 127.0.0.1:``port`` (0: a free one); ``say`` gets
    its link. Returns what stops it."""
    host, container_port = served
    where = "127.0.0.1" if host in ("0.0.0.0", "::", "") else host
    app = Application(
        descriptor,
        {container: Place(container, where, container_port)},
        token or "",
        timeout=5.0,
        how_to_start="the container serving this console stopped answering",
        mode="single process",
    )
    hub = ConsoleHub(max_viewers=32, max_watchers=8 if not token and is_loopback(where) else 0)
    console_token = secrets.token_urlsafe(16)
    session = LiveSession(hub, console_token, app)
    stack = contextlib.ExitStack()
    stack.callback(session.close)
    try:
        session.attach()
        site = session.site()
        refusals = console_refusals(site)
        web = create_app(site, hub, session, allowed_hosts=allowed_names(HOST), refusals=refusals)
        url = stack.enter_context(serving(web, refusals, host=HOST, port=port))
    except BaseException:
        stack.close()
        raise
    say(f"{container}: console: {url}/#token={console_token} (the link carries its token)")
    return stack.close
