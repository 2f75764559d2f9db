"""``python -m weblab_console [--host 127.0.0.1] [--port 8765] [--speed 1]``: the WebLab console.

Serves the console on uvicorn and prints its URL, which carries the session's token (random per
start: whoever has the link may drive). Run from ``samples/weblab`` with the generated application
built into ``samples/weblab/app`` (``make console`` does both). Ctrl-C stops it.
"""

from __future__ import annotations

import argparse
import logging
import secrets
import sys

import uvicorn

from weblab_console.hub import ConsoleHub
from weblab_console.server import create_app
from weblab_console.serving import free_port
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
    parser.add_argument("--viewers", type=int, default=32, help="most viewers at once (default 32)")
    parser.add_argument(
        "--start", metavar="PROFILE", help="start an experiment on this network at once"
    )
    parser.add_argument("--seed", type=int, default=0, help="the seed of --start (default 0)")
    args = parser.parse_args(argv)
    if not 0 <= args.port <= 65535 or args.speed < 0 or args.viewers < 1:
        parser.error("--port must be 0..65535, --speed >= 0, --viewers >= 1")
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    token = secrets.token_urlsafe(16)
    hub = ConsoleHub(max_viewers=args.viewers)
    session = ConsoleSession(hub, token, speed=args.speed)
    try:
        if args.start:
            session.start(args.start, args.seed)
    except Exception as err:
        print(f"weblab_console: cannot start the experiment: {err}", file=sys.stderr)
        return 2
    port = args.port or free_port(args.host)
    host = f"[{args.host}]" if ":" in args.host else args.host
    print(f"WebLab console: http://{host}:{port}/?token={token}", flush=True)
    print(
        "(the link carries the session's token: whoever has it may drive; Ctrl-C stops)", flush=True
    )
    config = uvicorn.Config(
        create_app(hub, session), host=args.host, port=port, log_level="warning", ws_max_size=65536
    )
    try:
        uvicorn.Server(config).run()
    except KeyboardInterrupt:  # uvicorn shut down cleanly, then passes Ctrl-C on
        pass
    finally:
        session.close()
    print("WebLab console stopped", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
