"""Two containers in two OS processes talking over Pyro5 on loopback, and what happens when the
remote one dies mid-call (a real child process; bounded timeouts)."""

from __future__ import annotations

import os
import select
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import ClassVar

import pytest

from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort
from acordcs.runtime.container import Container
from acordcs.runtime.errors import RemoteCallError, RemoteTimeoutError, RemoteUnreachableError
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.ports import async_port, sync_port

HELPER = Path(__file__).parents[1] / "support" / "remote_container.py"
TIMEOUT = 1.0  # the connector's call timeout: keeps the failure tests quick


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class RemoteProcess:
    """The child container process; started and stopped by the tests, always cleaned up."""

    def __init__(self, port: int) -> None:
        self.port = port
        self.proc: subprocess.Popen[str] | None = None
        self.uri = ""

    def start(self) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, str(HELPER), str(self.port)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        ready, _, _ = select.select([self.proc.stdout], [], [], 30)
        line = self.proc.stdout.readline() if ready else ""
        if not line.startswith("READY "):
            self.kill()
            raise RuntimeError(f"remote container did not start: {line!r}")
        self.uri = line.split()[1]

    def kill(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
        if self.proc is not None:
            self.proc.wait(timeout=10)
            for stream in (self.proc.stdin, self.proc.stdout):
                if stream is not None:
                    stream.close()
        self.proc = None


class Navigator(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 0.0}
    ports = (sync_port("robot", role="required"), async_port("events", role="required"))

    def drive(self, speed: float) -> float:
        return self.port("robot").call("move", speed)

    def ask(self, operation: str, *args: object) -> object:
        return self.port("robot").call(operation, *args)

    def tell(self, message: object) -> None:
        self.port("events").notify(message)

    def local(self) -> str:
        return "still here"


class Heartbeat(Monitor):
    def acquire(self):
        return {"beats": self.ticks}


@pytest.fixture
def remote():
    proc = RemoteProcess(free_port())
    proc.start()
    yield proc
    proc.kill()


@pytest.fixture
def local(remote):
    container = Container("local")  # real time, like a deployed container
    container.install_factory(ComponentFactory("Navigator", Navigator))
    container.create("Navigator", "nav")
    connector = RemoteConnector(timeout=TIMEOUT)
    container.connect("nav.robot", RemotePort(remote.uri, "robot", "control"), connector=connector)
    container.connect("nav.events", RemotePort(remote.uri, "robot", "events"), connector=connector)
    container.add_monitor(Heartbeat("heartbeat", frequency=50.0, attributes={"beats": 0}))
    yield container
    container.close()


def wait_for(predicate, seconds: float = 10.0) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.02)
    return False


def all_stopped(pid: int) -> bool:
    states = []
    for stat in Path(f"/proc/{pid}/task").glob("*/stat"):
        try:
            states.append(stat.read_text().rsplit(")", 1)[1].split()[0])
        except OSError:
            continue
    return bool(states) and all(state in ("T", "t") for state in states)


def test_components_in_two_processes_call_and_notify(local):
    nav = local.find("nav")
    assert nav.drive(0.4) == 0.4
    assert nav.ask("pid") != os.getpid()
    nav.tell({"stripe": "lost", "at": [1, 2]})
    assert wait_for(lambda: nav.ask("received") == [{"stripe": "lost", "at": [1, 2]}])


def test_bytes_cross_as_bytes_both_ways(local):
    # serpent sends bytes as a base64 dict; the connector gives them back as bytes
    frame = local.find("nav").ask("frame", b"\xff\xd8JPEG")
    assert frame == b"\xff\xd8JPEG" + bytes(range(256))


def test_remote_component_error_comes_back_as_a_clear_error(local):
    with pytest.raises(RemoteCallError, match=r"remote ComponentError: .*robot refuses") as info:
        local.find("nav").ask("crash")
    assert "robot.control" in str(info.value)
    with pytest.raises(RemoteCallError, match="has no operation 'fly'"):
        local.find("nav").ask("fly")


def test_remote_killed_mid_call_times_out_container_carries_on_and_recovers(local, remote):
    nav = local.find("nav")
    assert nav.drive(1.0) == 1.0
    threading.Timer(0.3, remote.kill).start()
    # The remote would take 30 s; it dies after 0.3 s: the caller gets the error, not a hang.
    with pytest.raises(RemoteTimeoutError, match="may or may not have run remotely"):
        nav.ask("slow", 30)
    # The caller's container keeps running: local calls work and its monitor keeps ticking.
    assert nav.local() == "still here"
    beats = local.get_property("heartbeat", "beats")
    assert wait_for(lambda: local.get_property("heartbeat", "beats") > beats)
    # While the remote is down, calls fail fast and say so.
    with pytest.raises(RemoteUnreachableError, match="cannot reach the remote container"):
        nav.drive(2.0)
    # Back at the same address: calls succeed again through the same connector.
    remote.start()
    assert nav.drive(3.0) == 3.0
    assert local.faults.counts["component"] >= 2  # the failed calls were recorded with context


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="needs /proc to see the stop")
def test_hung_remote_gives_a_timeout_error_within_the_timeout(local, remote):
    nav = local.find("nav")
    assert nav.drive(1.0) == 1.0
    os.kill(remote.proc.pid, signal.SIGSTOP)
    # kill() returns before every thread of the target has stopped: wait until they all have.
    assert wait_for(lambda: all_stopped(remote.proc.pid))
    try:
        with pytest.raises(RemoteTimeoutError, match=f"within {TIMEOUT:g} s"):
            nav.drive(2.0)
    finally:
        os.kill(remote.proc.pid, signal.SIGCONT)
    assert nav.drive(4.0) == 4.0


def test_one_proxy_per_thread(local):
    nav = local.find("nav")
    results = []

    def worker(n: int) -> None:
        results.append(nav.drive(float(n)))

    threads = [threading.Thread(target=worker, args=(n,)) for n in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(10)
    assert sorted(results) == [0.0, 1.0, 2.0, 3.0]
    connector = local.connections()[0].connector
    owners = [thread for thread, _proxy in connector._all]
    assert len(owners) == len(set(owners)) == 4  # each thread made its own proxy


def test_local_server_serves_this_container_too():
    # Both directions: this process can serve its own container for a remote peer.
    with Container("here") as here:
        here.install_factory(ComponentFactory("Navigator", Navigator))
        here.create("Navigator", "nav")
        with ContainerServer(here) as server:
            import Pyro5.api

            with Pyro5.api.Proxy(server.uri) as proxy:
                proxy._pyroTimeout = TIMEOUT
                assert proxy.ping() == "here"
                assert proxy.describe()["components"]["nav"]["type"] == "Navigator"
