"""The console served by uvicorn in a background thread of this process (for tests, the benchmark
and the screenshot script): ``with serving(hub, session) as url: ...``; leaving the block stops
the server and the session's experiment."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

import uvicorn

from weblab_console.guard import allowed_names
from weblab_console.hub import ConsoleHub
from weblab_console.server import Session, console_refusals, create_app, quiet_uvicorn


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port nobody listens on now (the OS picks it)."""
    with socket.socket() as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


@contextmanager
def serving(
    hub: ConsoleHub, session: Session, *, host: str = "127.0.0.1", port: int = 0
) -> Iterator[str]:
    """The console's base URL (``http://host:port``) while the block runs."""
    port = port or free_port(host)
    refusals = console_refusals()
    config = uvicorn.Config(
        create_app(hub, session, allowed_hosts=allowed_names(host), refusals=refusals),
        host=host,
        port=port,
        log_level="warning",
        ws_max_size=65536,
    )
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, name="weblab-console-server", daemon=True)
    with quiet_uvicorn(refusals):
        thread.start()
        deadline = time.monotonic() + 20
        while not server.started:
            if not thread.is_alive() or time.monotonic() > deadline:
                raise RuntimeError(f"the console's server did not start on {host}:{port}")
            time.sleep(0.02)
        try:
            yield f"http://{host}:{port}"
        finally:
            # close() also drops the idle application the session keeps for the access service.
            end = getattr(session, "close", None) or getattr(session, "stop", None)
            if end is not None:
                end()
            server.should_exit = True
            thread.join(10)
