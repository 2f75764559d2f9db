"""The Pyro5 endpoint of a container under the attacks of issue 14 (loopback, bounded): no token,
another serializer, a port's handler called directly, idle sockets held open, and TLS with client
certificates and idle sockets (in a child process: Pyro5's SSL settings belong to the whole
process)."""

from __future__ import annotations

import socket
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any, ClassVar

import Pyro5.api
import Pyro5.errors
import pytest

from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort, container_uri
from acordcs.runtime.container import Container
from acordcs.runtime.errors import RemoteCallError, RemoteUnreachableError
from acordcs.runtime.ports import async_port, sync_port

TOKEN = "s3cret-token-of-the-lab"


class Robot(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 0.0}
    ports = (
        sync_port("control"),
        sync_port("admin", operations=("status",)),
        async_port("events"),
        sync_port("out", role="required"),
    )

    def __init__(self) -> None:
        self.got: list[Any] = []

    def move(self, speed: float) -> float:
        self.set("speed", speed)
        return speed

    def status(self) -> str:
        return "ok"

    def on_events(self, message: Any) -> None:
        self.got.append(message)


@pytest.fixture
def served(monkeypatch):
    monkeypatch.delenv("ACORDCS_TOKEN", raising=False)
    container = Container("lab")
    container.install_factory(ComponentFactory("Robot", Robot))
    container.create("Robot", "robot")
    server = ContainerServer(container, token=TOKEN, handshake_timeout=1.0)
    yield container, server
    server.close()
    container.close()


def call(server: ContainerServer, *args: Any, token: str | None = TOKEN) -> Any:
    connector = RemoteConnector(timeout=3.0, token=token)
    try:
        return connector.request(server.uri, "call", *args, where="test")
    finally:
        connector.close()


def test_a_caller_with_the_token_calls_one_without_it_cannot_connect(served):
    _, server = served
    assert call(server, "robot", "control", "move", [0.5], {}) == 0.5
    for wrong in (None, "guess"):
        with pytest.raises(RemoteUnreachableError, match="wrong or missing token"):
            call(server, "robot", "control", "move", [0.5], {}, token=wrong)


def test_the_token_comes_from_the_environment(served, monkeypatch):
    _, server = served
    monkeypatch.setenv("ACORDCS_TOKEN", TOKEN)
    connector = RemoteConnector(timeout=3.0)
    try:
        assert connector.request(server.uri, "ping", where="test") == "lab"
    finally:
        connector.close()


@pytest.mark.parametrize("serializer", ["marshal", "json"])
def test_other_serializers_are_refused(served, serializer):
    _, server = served
    with Pyro5.api.Proxy(server.uri) as proxy:
        proxy._pyroSerializer = serializer
        proxy._pyroHandshake = TOKEN
        proxy._pyroTimeout = 3.0
        with pytest.raises(Pyro5.errors.SecurityError, match="serpent serializer only"):
            proxy.call("robot", "control", "move", [9.0], {})


def test_the_daemon_lists_nothing(served):
    _, server = served
    with Pyro5.api.Proxy(f"PYRO:Pyro.Daemon@{server.host}:{server.port}") as daemon:
        daemon._pyroHandshake = TOKEN
        daemon._pyroTimeout = 3.0
        with pytest.raises(Pyro5.errors.SecurityError, match="does not list"):
            daemon.registered()


def test_only_the_operations_behind_a_provided_port_are_callable(served):
    container, server = served
    # a port's handler would bypass the port's queue
    with pytest.raises(RemoteCallError, match="does not expose 'on_events'"):
        call(server, "robot", "control", "on_events", ["forged"], {})
    # a port that declares its operations exposes those only
    assert call(server, "robot", "admin", "status", [], {}) == "ok"
    with pytest.raises(RemoteCallError, match="does not expose 'move'"):
        call(server, "robot", "admin", "move", [7.0], {})
    # deliveries go to asynchronous or stream ports only, never a synchronous port's operations
    connector = RemoteConnector(timeout=3.0, token=TOKEN)
    try:
        with pytest.raises(
            RemoteCallError, match="deliveries arrive at asynchronous or stream ports"
        ):
            connector.request(server.uri, "deliver", "robot", "out", "x", where="test")
    finally:
        connector.close()
    assert container.get_property("robot", "speed") == 0.0


def test_idle_sockets_without_a_handshake_do_not_lock_callers_out(served):
    _, server = served
    idle = []
    try:
        for _ in range(100):
            idle.append(socket.create_connection((server.host, server.port), timeout=5))
        # The idle connections stay open on this side while a real caller calls.
        assert call(server, "robot", "control", "move", [1.5], {}) == 1.5
    finally:
        for s in idle:
            s.close()


def test_a_served_non_loopback_host_needs_a_token(monkeypatch):
    from acordcs.runtime.errors import ConfigurationError

    monkeypatch.delenv("ACORDCS_TOKEN", raising=False)
    container = Container("open")
    try:
        with pytest.raises(ConfigurationError, match="without a token"):
            ContainerServer(container, host="0.0.0.0")
    finally:
        container.close()


def openssl(*args: str, cwd: Path) -> None:
    subprocess.run(["openssl", *args], cwd=cwd, check=True, capture_output=True, timeout=60)


def make_certificates(d: Path) -> None:
    """A CA, a server certificate for 127.0.0.1 and a client certificate, signed by the CA."""
    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj", "/CN=test-ca",
            "-keyout", "ca.key", "-out", "ca.pem", cwd=d)  # fmt: skip
    (d / "san.ext").write_text("subjectAltName=IP:127.0.0.1\n")
    for name in ("server", "client"):
        openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", f"/CN={name}",
                "-keyout", f"{name}.key", "-out", f"{name}.csr", cwd=d)  # fmt: skip
        openssl("x509", "-req", "-in", f"{name}.csr", "-CA", "ca.pem", "-CAkey", "ca.key",
                "-CAcreateserial", "-days", "2", "-extfile", "san.ext",
                "-out", f"{name}.pem", cwd=d)  # fmt: skip


CHILD = textwrap.dedent(
    """
    import socket, ssl, sys
    from acordcs.runtime.connectors.pyrogate import TLSFiles
    from acordcs.runtime.connectors.endpoint import ContainerServer
    from acordcs.runtime.connectors.remote import RemoteConnector
    from acordcs.runtime.container import Container
    d = sys.argv[1]
    c = Container("tls")
    server = ContainerServer(c, token="t", tls=TLSFiles(f"{d}/server.pem", f"{d}/server.key", f"{d}/ca.pem"))
    client = RemoteConnector(timeout=5, token="t", tls=TLSFiles(f"{d}/client.pem", f"{d}/client.key", f"{d}/ca.pem"))
    # idle TCP connections (no TLS handshake) must not hold the real caller up
    idle = [socket.create_connection((server.host, server.port)) for _ in range(20)]
    print("with-cert", client.request(server.uri, "ping", where="child"))
    # A client without a certificate: the TLS session is refused.
    ctx = ssl.create_default_context(cafile=f"{d}/ca.pem")
    try:
        with socket.create_connection((server.host, server.port), timeout=5) as raw:
            with ctx.wrap_socket(raw, server_hostname="127.0.0.1") as s:
                s.sendall(b"PYRO")
                print("without-cert", "read", s.recv(10))
    except (ssl.SSLError, OSError) as exc:
        print("without-cert", "refused", type(exc).__name__)
    client.close(); server.close(); c.close()
    """
)


def test_tls_with_client_certificates(tmp_path):
    try:
        make_certificates(tmp_path)
    except (OSError, subprocess.CalledProcessError) as exc:
        pytest.skip(f"openssl cannot make test certificates here: {exc}")
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0] == "with-cert tls"
    assert lines[1].startswith("without-cert refused"), lines[1]


def test_uri_is_unchanged_by_the_gate(served):
    _, server = served
    assert server.uri == container_uri("lab", server.host, server.port)
    assert RemotePort(server.uri, "robot", "control").qualified_name.startswith("robot.control@")
