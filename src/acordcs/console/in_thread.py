"""A console's ASGI application served by uvicorn in a background thread of this process (the
``acordcs-gen console`` command, tests, benchmarks, screenshots): ``with serving(app, refusals)
as url: ...``; leaving the block stops the server."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import uvicorn
from starlette.applications import Starlette

from acordcs.console.web_app import quiet_uvicorn
from acordcs.runtime.refusals import Refusals

WS_MAX_SIZE = 65536
"""Bytes of one WebSocket frame uvicorn takes (the console reads at most 4 KB of a message)."""


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port nobody listens on now (the OS picks it)."""
    with socket.socket() as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def server_config(app: Starlette, host: str, port: int) -> uvicorn.Config:
    """How every console runs on uvicorn: quiet but for warnings, frames of at most
    :data:`WS_MAX_SIZE` bytes."""
    return uvicorn.Config(app, host=host, port=port, log_level="warning", ws_max_size=WS_MAX_SIZE)


class AnnouncingServer(uvicorn.Server):
    """uvicorn's server, calling ``announce`` once it listens (a console prints its link then:
    the link is also the sign that the console is ready, and its Ctrl-C handling in place)."""

    def __init__(self, config: uvicorn.Config, announce: Callable[[], None]) -> None:
        super().__init__(config)
        self.announce = announce

    async def startup(self, sockets: list | None = None) -> None:
        await super().startup(sockets)
        if self.started:
            self.announce()


@contextmanager
def serving(
    app: Starlette, refusals: Refusals, *, host: str = "127.0.0.1", port: int = 0
) -> Iterator[str]:
    """The console's base URL (``http://host:port``) while the block runs."""
    port = port or free_port(host)
    server = uvicorn.Server(server_config(app, host, port))
    thread = threading.Thread(target=server.run, name="acordcs-console-server", daemon=True)
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
            server.should_exit = True
            thread.join(10)
