"""``python -m weblab_console [--host 127.0.0.1] [--port 8765] [--speed 1] [--attach APP]``: the
WebLab console.

Serves the console on uvicorn and prints its URL, whose fragment (``#token=...``, never sent to a
server) carries the session's token (random per start: whoever has the link may drive). Run from
``samples/weblab`` with the generated application built into ``samples/weblab/app`` (``make
console`` does both). Without ``--attach`` it runs the experiment in this process, on a simulated
clock; with ``--attach APP`` it attaches to the application built in ``APP`` and started by its
scripts (``make live-console``), found as those scripts find it (``APP/bin/env.sh``, with the
environment they ran with). Ctrl-C stops it.
"""

from __future__ import annotations

import argparse
import logging
import secrets
import signal
import sys
from pathlib import Path

from acordcs.console.attaching import Application, AttachError
from acordcs.console.fanout import ConsoleHub
from acordcs.console.in_thread import AnnouncingServer, free_port, server_config
from acordcs.console.live_session import LiveSession
from acordcs.console.site_guard import allowed_names, host_name, is_loopback
from weblab_console.attached import HOW_TO_START, TIMEOUT
from weblab_console.server import (
    console_refusals,
    create_app,
    live_console,
    quiet_uvicorn,
    simulation_console,
)
from weblab_console.session import ConsoleSession


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m weblab_console", description=__doc__.split("\n")[0]
    )
    parser.add_argument(
        "--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)"
    )
    parser.add_argument("--port", type=int, default=0, help="port (default: a free one)")
    parser.add_argument(
        "--speed",
        type=float,
        default=1.0,
        help="simulated seconds per wall second (0: as fast as it runs)",
    )
    parser.add_argument(
        "--viewers",
        type=int,
        default=32,
        help="most viewers holding the token at once (default 32)",
    )
    parser.add_argument(
        "--watchers",
        type=int,
        default=8,
        help="most viewers without the token (watching only) at once (default 8)",
    )
    parser.add_argument(
        "--allow-host",
        action="append",
        default=[],
        metavar="NAME",
        help="a name browsers may reach the console by besides the address it listens on "
        "(repeat for each; e.g. the name of this machine with --host 0.0.0.0)",
    )
    parser.add_argument(
        "--start", metavar="PROFILE", help="start an experiment on this network at once"
    )
    parser.add_argument("--seed", type=int, default=0, help="the seed of --start (default 0)")
    parser.add_argument(
        "--attach",
        metavar="APP",
        type=Path,
        help="attach to the application built in APP and started by its scripts (APP/bin) "
        "instead of running the experiment here",
    )
    args = parser.parse_args(argv)
    if not 0 <= args.port <= 65535 or args.speed < 0 or args.viewers < 1 or args.watchers < 0:
        parser.error("--port must be 0..65535, --speed >= 0, --viewers >= 1, --watchers >= 0")
    if args.attach is not None and args.start:
        parser.error("--start runs an experiment here: not with --attach (the application runs)")
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    # TERM (kill, live.sh passing Ctrl-C on) stops as Ctrl-C does: uvicorn shuts down, then
    # raises the signal again, which must reach this handler, not the default (no cleanup).
    signal.signal(signal.SIGTERM, _interrupt)
    everywhere = args.host.strip("[]") in ("0.0.0.0", "::")
    if everywhere and not args.allow_host:
        parser.error(
            f"--host {args.host} listens on every address: name the one browsers will use with "
            "--allow-host NAME (the console refuses requests sent to any other name)"
        )
    allowed = allowed_names(args.host, args.allow_host)
    if not is_loopback(args.host):
        print(exposure_warning(args.host), file=sys.stderr, flush=True)
    token = secrets.token_urlsafe(16)
    hub = ConsoleHub(max_viewers=args.viewers, max_watchers=args.watchers)
    simulation: ConsoleSession | None = None
    console: LiveSession
    if args.attach is not None:
        try:
            app = Application.built_in(args.attach, TIMEOUT, HOW_TO_START)
            console = live_console(hub, token, app)
        except AttachError as err:
            print(f"weblab_console: cannot attach to {args.attach}: {err}", file=sys.stderr)
            return 2
    else:
        simulation = ConsoleSession(hub, token, speed=args.speed)
        console = simulation_console(hub, simulation)
    port = args.port or free_port(args.host)
    shown = host_name(args.allow_host[0]) if everywhere else args.host.strip("[]")
    shown = f"[{shown}]" if ":" in shown else shown
    link = (
        f"WebLab console: http://{shown}:{port}/#token={token}\n"
        "(the link carries the session's token: whoever has it may drive; Ctrl-C stops)"
    )
    try:  # Ctrl-C at any moment, also before the server runs, stops cleanly
        try:
            attached = console.attach()
        except AttachError as err:
            print(f"weblab_console: cannot attach to {args.attach}: {err}", file=sys.stderr)
            return 2
        if simulation is None:
            print(f"WebLab console: attached to {attached}", flush=True)
        elif args.start:
            try:
                simulation.start(args.start, args.seed)
            except Exception as err:
                print(f"weblab_console: cannot start the experiment: {err}", file=sys.stderr)
                return 2
        refusals = console_refusals()
        config = server_config(
            create_app(hub, console, allowed_hosts=allowed, refusals=refusals), args.host, port
        )
        with quiet_uvicorn(refusals):
            AnnouncingServer(config, lambda: print(link, flush=True)).run()
    except KeyboardInterrupt:  # uvicorn shut down cleanly, then passes Ctrl-C on
        pass
    finally:
        console.close()
    print("WebLab console stopped", flush=True)
    return 0


def _interrupt(signum: int, frame: object) -> None:
    raise KeyboardInterrupt


def exposure_warning(host: str) -> str:
    """What listening on ``host``, not a loopback address, exposes."""
    return (
        f"weblab_console: warning: --host {host} is not a loopback address: anyone who can reach "
        "this machine's port can watch the experiment (up to --watchers at once), and the link's "
        "token, the cameras and every command travel in clear text (no TLS), where anyone on the "
        "network path can read the token and drive; prefer --host 127.0.0.1 and an SSH tunnel "
        "(ssh -L PORT:127.0.0.1:PORT this-machine)"
    )


if __name__ == "__main__":
    sys.exit(main())
