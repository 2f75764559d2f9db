"""A TCP relay that adds latency, for tests on network hosts without the kernel's ``netem``:
``python -m tests.support.latency_relay LISTEN_HOST:PORT TARGET_HOST:PORT DELAY_S [...]``
(one ``LISTEN TARGET DELAY`` triple per relayed port), run inside a host's namespace.

Each connection accepted at LISTEN is joined to a new connection to TARGET; each chunk read from
either side is written to the other ``DELAY_S`` seconds after it was read, in order, while the
next chunks are read meanwhile: a one-way latency that does not cut the bandwidth (the link's
``tc tbf`` does that). Not emulated: jitter and loss. Prints ``relaying`` once every port listens
(what a test waits for); stops on SIGTERM."""

from __future__ import annotations

import collections
import contextlib
import socket
import sys
import threading
import time


def _address(text: str) -> tuple[str, int]:
    host, _, port = text.rpartition(":")
    return host, int(port)


def _pipe(source: socket.socket, sink: socket.socket, delay: float) -> None:
    """Copy ``source`` to ``sink``, each chunk ``delay`` s after it was read."""
    queue: collections.deque[tuple[float, bytes]] = collections.deque()
    ready = threading.Condition()

    def write() -> None:
        while True:
            with ready:
                ready.wait_for(lambda: queue)
                due, chunk = queue.popleft()
            wait = due - time.monotonic()
            if wait > 0:
                time.sleep(wait)
            if not chunk:
                with contextlib.suppress(OSError):
                    sink.shutdown(socket.SHUT_WR)
                return
            try:
                sink.sendall(chunk)
            except OSError:
                return

    writer = threading.Thread(target=write, daemon=True)
    writer.start()
    while True:
        try:
            chunk = source.recv(65536)
        except OSError:
            chunk = b""
        with ready:
            queue.append((time.monotonic() + delay, chunk))
            ready.notify()
        if not chunk:
            break
    writer.join()
    for sock in (source, sink):
        with contextlib.suppress(OSError):
            sock.close()


def _join(client: socket.socket, target: tuple[str, int], delay: float) -> None:
    """Join ``client`` to a new connection to ``target``, in a thread of its own: a target that
    does not answer (its link down) holds this connection only, never the next ones."""
    try:
        upstream = socket.create_connection(target, timeout=10)
    except OSError:
        client.close()
        return
    upstream.settimeout(None)
    for sock in (client, upstream):
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    threading.Thread(target=_pipe, args=(client, upstream, delay), daemon=True).start()
    _pipe(upstream, client, delay)


def _serve(listener: socket.socket, target: tuple[str, int], delay: float) -> None:
    while True:
        client, _ = listener.accept()
        threading.Thread(target=_join, args=(client, target, delay), daemon=True).start()


def main(argv: list[str]) -> None:
    if not argv or len(argv) % 3:
        sys.exit("usage: latency_relay LISTEN_HOST:PORT TARGET_HOST:PORT DELAY_S [...]")
    threads = []
    for i in range(0, len(argv), 3):
        listener = socket.create_server(_address(argv[i]))
        threads.append(threading.Thread(target=_serve, daemon=True,
                                        args=(listener, _address(argv[i + 1]), float(argv[i + 2]))))  # fmt: skip
    for thread in threads:
        thread.start()
    print("relaying", flush=True)
    threading.Event().wait()


if __name__ == "__main__":
    main(sys.argv[1:])
