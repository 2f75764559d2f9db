"""A small HTTP server for factory packages (tests, examples, a lab network): http.server in a thread."""

from __future__ import annotations

import threading
from functools import partial
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import quote


class _QuietHandler(SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: object) -> None:  # keep test and example output clean
        pass


class FactoryServer:
    """Serve the files of ``directory`` over HTTP on ``host:port`` (0: a free port) until closed.

    ``server.url("linefollower-1.2.0.zip")`` is the package's URL, e.g. for a description's location.
    """

    def __init__(self, directory: str | Path, host: str = "127.0.0.1", port: int = 0) -> None:
        self.directory = Path(directory)
        if not self.directory.is_dir():
            raise NotADirectoryError(f"{self.directory} is not a directory of factory packages")
        handler = partial(_QuietHandler, directory=str(self.directory))
        self._server = ThreadingHTTPServer((host, port), handler)
        self._server.daemon_threads = True
        self.host, self.port = self._server.server_address[:2]
        # a short poll interval makes close() quick (shutdown waits for the next poll)
        self._thread = threading.Thread(
            target=self._server.serve_forever,
            args=(0.05,),
            name="acordcs-factory-http",
            daemon=True,
        )
        self._thread.start()

    def url(self, filename: str) -> str:
        return f"http://{self.host}:{self.port}/{quote(filename)}"

    def close(self) -> None:
        """Stop serving, close the socket and join the thread. Idempotent."""
        if self._thread.is_alive():
            self._server.shutdown()
            self._thread.join(timeout=5)
        self._server.server_close()

    def __enter__(self) -> FactoryServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
