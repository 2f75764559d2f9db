"""``acordcs-gen console APPDIR``: a browser console attached to the running application."""

from __future__ import annotations

import secrets
from pathlib import Path
from typing import NoReturn

import click

from acordcs.diagnostics import printable


@click.command()
@click.argument("app_dir", metavar="APPDIR", type=click.Path(file_okay=False))
@click.option(
    "--model",
    type=click.Path(dir_okay=False, exists=True),
    help="The model file the page's updates are built from (acordcs-gen update MODEL -o APPDIR); "
    "without it, the page plans and applies no update.",
)
@click.option("--host", default="127.0.0.1", show_default=True, help="Address to listen on.")
@click.option(
    "--port", type=click.IntRange(0, 65535), default=0, help="Port (default: a free one)."
)
@click.option(
    "--allow-host",
    multiple=True,
    metavar="NAME",
    help="A name browsers may reach the console by besides the address it listens on (repeat).",
)
@click.option(
    "--viewers",
    type=click.IntRange(min=1),
    default=32,
    show_default=True,
    help="Most viewers holding the console's token at once.",
)
@click.option(
    "--watchers",
    type=click.IntRange(min=0),
    default=None,
    help="Most viewers without the token (watching only) at once; default 8 for an application "
    "started without a token on loopback, else 0: only the link's holders see it.",
)
@click.option(
    "--timeout",
    type=click.FloatRange(min=0.1),
    default=5.0,
    show_default=True,
    help="Seconds to wait for a container's answer.",
)
def console(
    app_dir: str,
    model: str | None,
    host: str,
    port: int,
    allow_host: tuple[str, ...],
    viewers: int,
    watchers: int | None,
    timeout: float,
) -> None:
    """Serve on HOST (127.0.0.1) a page that shows and drives the application built in APPDIR and
    started by its scripts (found as acordcs-gen update finds it: APPDIR/bin/env.sh with the same
    environment, ACORDCS_RUN_DIR, ACORDCS_TOKEN, ACORDCS_<C>_HOST, ACORDCS_<C>_PORT): its
    architecture drawn from its descriptor, each monitor's values plotted live, each policy
    set's firings with their rules' degrees, faults and updates; holding the token of the link
    it prints, call an operation of a provided port, plan and apply an update from --model.

    The link's fragment (#token=..., never sent to a server) carries the console's token, new at
    each start. Ctrl-C stops the console (not the application). What it checks: docs/console.md.

    Exit 0 when stopped by Ctrl-C, 2 on usage errors, an APPDIR that is not a built application,
    or a container that does not answer.

    \b
    Examples:
      acordcs-gen console app
      ACORDCS_RUN_DIR=/tmp/run acordcs-gen console app --model model.uml --port 8765
    """
    import logging
    import signal

    from acordcs.console.attaching import AttachError
    from acordcs.console.fanout import ConsoleHub
    from acordcs.console.in_thread import AnnouncingServer, free_port, server_config
    from acordcs.console.live_session import LiveSession
    from acordcs.console.panels import panel_table
    from acordcs.console.site_guard import allowed_names, host_name, is_loopback
    from acordcs.console.web_app import console_refusals, create_app, quiet_uvicorn
    from acordcs.runtime.connectors.pyrogate import is_loopback as loopback_host

    app = Path(app_dir)
    shown = printable(click.format_filename(app_dir))
    if not app.is_dir():
        _fail(f"{shown} is not a directory: give the application's directory (built by build)", 2)
    everywhere = host.strip("[]") in ("0.0.0.0", "::")
    if everywhere and not allow_host:
        _fail(
            f"--host {host} listens on every address: name the one browsers will use with "
            "--allow-host NAME (the console refuses requests sent to any other name)",
            2,
        )
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    token = secrets.token_urlsafe(16)
    hub = ConsoleHub(max_viewers=viewers, max_watchers=8)
    panels = panel_table()  # what installed packages add to the page (acordcs.console_panels)
    try:
        session = LiveSession.attached(
            hub, token, app, model=Path(model) if model else None, timeout=timeout, panels=panels
        )
    except AttachError as err:
        _fail(f"cannot attach to {shown}: {printable(str(err))}", 2)
    for problem in panels.take_problems():  # a broken plug-in never stops the console
        click.echo(f"acordcs-gen console: warning: {printable(problem)}", err=True)
    if watchers is None:
        open_app = not session.app.token and all(
            loopback_host(p.host) for p in session.app.places.values()
        )
        watchers = 8 if open_app else 0
    hub.max_watchers = watchers
    if not is_loopback(host):
        click.echo(
            f"acordcs-gen console: warning: --host {host} is not a loopback address: the link's "
            "token and everything the page shows travel in clear text (no TLS); prefer "
            "127.0.0.1 and an SSH tunnel (ssh -L PORT:127.0.0.1:PORT this-machine)",
            err=True,
        )
    site = session.site()
    port = port or free_port(host)
    name = host_name(allow_host[0]) if everywhere else host.strip("[]")
    name = f"[{name}]" if ":" in name else name
    link = (
        f"acordcs console: http://{name}:{port}/#token={token}\n"
        "(the link carries the console's token: whoever has it may call operations and apply "
        "updates; Ctrl-C stops the console)"
    )
    signal.signal(signal.SIGTERM, _interrupt)
    refusals = console_refusals(site)
    try:
        try:
            click.echo(f"acordcs console: attached to {session.attach()}")
        except AttachError as err:
            _fail(f"cannot attach to {shown}: {printable(str(err))}", 2)
        application = create_app(
            site, hub, session, allowed_hosts=allowed_names(host, allow_host), refusals=refusals
        )
        with quiet_uvicorn(refusals):
            AnnouncingServer(server_config(application, host, port), lambda: click.echo(link)).run()
    except KeyboardInterrupt:
        pass
    finally:
        session.close()
    click.echo("acordcs console stopped")


def _interrupt(signum: int, frame: object) -> None:
    raise KeyboardInterrupt


def _fail(message: str, code: int) -> NoReturn:
    click.echo(f"acordcs-gen console: {message}", err=True)
    raise click.exceptions.Exit(code)


__all__ = ["console"]
