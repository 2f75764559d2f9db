"""One HTTP(S) download with a size limit, a per-read ``timeout`` and an overall ``deadline``.

urllib's ``timeout`` bounds each socket operation only: a server sending one byte per second
never trips it. Here a timer shuts the connection's socket down at the deadline, which ends a read
blocked anywhere (status line, headers or body) at once.
"""

from __future__ import annotations

import contextlib
import http.client
import socket
import threading
import time
import urllib.request
from typing import Any


class DeadlineExceeded(OSError):
    """The download did not finish within its deadline."""


class _Watch:
    """The sockets of one download, shut down together when its deadline passes."""

    def __init__(self) -> None:
        self.sockets: list[socket.socket] = []
        self.expired = False
        self.lock = threading.Lock()

    def add(self, sock: socket.socket) -> None:
        with self.lock:
            self.sockets.append(sock)
            if self.expired:
                _shutdown(sock)

    def expire(self) -> None:
        with self.lock:
            self.expired = True
            for sock in self.sockets:
                _shutdown(sock)


def _shutdown(sock: socket.socket) -> None:
    with contextlib.suppress(OSError):  # already closed
        sock.shutdown(socket.SHUT_RDWR)


def _handlers(watch: _Watch) -> list[urllib.request.BaseHandler]:
    class Watched(http.client.HTTPConnection):
        def connect(self) -> None:
            super().connect()
            watch.add(self.sock)

    class WatchedTLS(http.client.HTTPSConnection):
        def connect(self) -> None:
            super().connect()
            watch.add(self.sock)

    class HTTP(urllib.request.HTTPHandler):
        def http_open(self, req: Any) -> Any:
            return self.do_open(Watched, req)

    class HTTPS(urllib.request.HTTPSHandler):
        def https_open(self, req: Any) -> Any:
            return self.do_open(WatchedTLS, req)

    return [HTTP(), HTTPS()]


def fetch(url: str, *, timeout: float, deadline: float, max_bytes: int) -> bytes:
    """The body at ``url``, at most ``max_bytes + 1`` bytes (the caller sees it is too large).
    Raises urllib's errors, or :class:`DeadlineExceeded` after ``deadline`` seconds in all."""
    watch = _Watch()
    timer = threading.Timer(deadline, watch.expire)
    timer.daemon = True
    opener = urllib.request.build_opener(*_handlers(watch))
    end = time.monotonic() + deadline
    timer.start()
    try:
        with opener.open(url, timeout=timeout) as response:
            chunks, size = [], 0
            while size <= max_bytes:
                chunk = response.read1(min(65536, max_bytes + 1 - size))
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
                if time.monotonic() > end:
                    break
            if time.monotonic() > end or watch.expired:
                raise DeadlineExceeded(f"not complete within its deadline of {deadline:g} s")
            return b"".join(chunks)
    except OSError:
        if watch.expired:
            raise DeadlineExceeded(f"not complete within its deadline of {deadline:g} s") from None
        raise
    except http.client.HTTPException as err:
        if watch.expired:
            raise DeadlineExceeded(f"not complete within its deadline of {deadline:g} s") from None
        raise OSError(f"{type(err).__name__}: {err}") from None
    finally:
        timer.cancel()
