"""A mosquitto for the MQTT benchmarks: its own configuration (anonymous on loopback, large queues,
no persistence, no log), a free port on 127.0.0.1, stopped and cleaned up at the end of the block.
Not a benchmark itself (`make bench` runs only bench_*.py)."""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

MOSQUITTO = "/usr/sbin/mosquitto"
PIDS: dict[int, int] = {}
"""port -> process id of each broker running (for benchmarks that measure its CPU)."""

CONF = """\
listener {port} {address}
allow_anonymous true
set_tcp_nodelay true
max_queued_messages 1000000
max_inflight_messages 1000
persistence false
log_dest none
"""


def write_config(directory: Path, address: str, port: int, extra: str = "") -> Path:
    """``directory``/mosquitto.conf: this module's configuration listening on ``address``:``port``,
    with the lines ``extra`` after it; returns its path."""
    conf = directory / "mosquitto.conf"
    conf.write_text(CONF.format(port=port, address=address) + extra)
    return conf


def available() -> bool:
    """Whether mosquitto is installed (the benchmarks print a skip line without it)."""
    return os.access(MOSQUITTO, os.X_OK)


@contextlib.contextmanager
def loopback_broker() -> Iterator[int]:
    """A running mosquitto; yields its port on 127.0.0.1."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    workdir = Path(tempfile.mkdtemp(prefix="bench-mosquitto-"))
    conf = write_config(workdir, "127.0.0.1", port)
    broker = subprocess.Popen(
        [MOSQUITTO, "-c", str(conf)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    PIDS[port] = broker.pid
    try:
        for _ in range(200):
            try:
                socket.create_connection(("127.0.0.1", port), timeout=0.1).close()
                break
            except OSError:
                time.sleep(0.02)
        yield port
    finally:
        PIDS.pop(port, None)
        broker.terminate()
        broker.wait(timeout=5)
        conf.unlink()
        workdir.rmdir()
