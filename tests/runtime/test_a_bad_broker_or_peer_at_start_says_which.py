"""What stops a container's process at its start, or its first call, when a peer is wrong: a
context broker (``--context mqtt://...``, :mod:`acordcs.runtime.broker_setting`) that refuses the
login, that is not there, or that speaks something other than MQTT; a remote container's address
where something that is not Pyro5 answers, or answers nothing. Each is one error naming the
container (or connection), the host and the port, within the timeout given, never a hang.

Everything is on loopback: a real mosquitto with a password file, and plain sockets the test
serves. A host name that does not resolve is tested inside a network namespace, where no name
reaches a real DNS server (tests/samples/weblab/test_faults_on_network_hosts.py)."""

from __future__ import annotations

import socket
import subprocess
import threading
import time
from collections.abc import Iterator

import pytest

from acordcs.runtime.broker_setting import BrokerSetting, open_broker, parse_context
from acordcs.runtime.connectors.remote import RemoteConnector, container_uri
from acordcs.runtime.errors import ConfigurationError, RemoteTimeoutError, RemoteUnreachableError
from acordcs.runtime.launcher import Launcher
from tests.support.services import free_port, mosquitto_binary, wait_for

BOUND = 1.0  # the timeout given: each failure must come within it (plus a margin for a loaded host)


def test_the_context_option_reads_embedded_and_broker_addresses() -> None:
    assert parse_context("embedded") is None and parse_context("") is None
    assert parse_context("mqtt://169.254.33.3") == BrokerSetting("169.254.33.3", 1883)
    assert parse_context("mqtt://lab%40x@ctx.invalid:8883") == BrokerSetting(
        "ctx.invalid", 8883, "lab@x"
    )
    assert str(BrokerSetting("::1", 1884, "u")) == "mqtt://u@[::1]:1884"
    assert parse_context("mqtt://h/lab/one/") == BrokerSetting("h", 1883, None, "lab/one")
    assert str(BrokerSetting("h", prefix="lab/one")) == "mqtt://h:1883/lab/one"
    for bad, said in [
        ("tcp://h", "is not 'embedded' or mqtt://"),
        ("mqtt://u:secret@h", "give the broker's password in $ACORDCS_MQTT_PASSWORD"),
        ("mqtt://h:99999", "the port is a whole number 1 to 65535"),
        ("mqtt://h:0", "the port is a whole number 1 to 65535"),
        ("mqtt://h/a/+", "has a wildcard or an empty level"),
        ("mqtt://h/a//b", "has a wildcard or an empty level"),
        ("mqtt://h?x=1", "no '?' or '#'"),
        ("mqtt://h/a/#", "no '?' or '#'"),
    ]:
        with pytest.raises(ValueError, match=None) as caught:
            parse_context(bad)
        assert said in str(caught.value), (bad, str(caught.value))


@pytest.fixture(scope="module")
def guarded_broker(tmp_path_factory: pytest.TempPathFactory) -> Iterator[int]:
    """A mosquitto on loopback that admits only user 'lab' with password 'right'."""
    binary = mosquitto_binary()
    work = tmp_path_factory.mktemp("guarded-broker")
    passwords = work / "passwd"
    passwords.write_text("")
    subprocess.run(["mosquitto_passwd", "-b", str(passwords), "lab", "right"], check=True,
                   capture_output=True, timeout=30)  # fmt: skip
    port = free_port()
    log = work / "mosquitto.log"
    (work / "mosquitto.conf").write_text(
        f"listener {port} 127.0.0.1\nallow_anonymous false\npassword_file {passwords}\n"
        f"log_dest file {log}\nuser root\n"
    )
    process = subprocess.Popen([binary, "-c", str(work / "mosquitto.conf")],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    try:
        assert wait_for(lambda: log.exists() and "listen socket" in log.read_text(), 10)
        yield port
    finally:
        process.terminate()
        process.wait(timeout=10)


def refused(setting: BrokerSetting) -> tuple[str, float]:
    start = time.monotonic()
    with pytest.raises(ConfigurationError) as caught:
        open_broker(setting, "WebLabSide", token=None, timeout=BOUND).close()
    return str(caught.value), time.monotonic() - start


def test_a_broker_refusing_the_login_is_said_with_the_user_to_give(
    guarded_broker: int, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level("WARNING")
    monkeypatch.setenv("ACORDCS_MQTT_PASSWORD", "wrong")
    for setting in (BrokerSetting("127.0.0.1", guarded_broker, "lab"),
                    BrokerSetting("127.0.0.1", guarded_broker)):  # fmt: skip
        message, took = refused(setting)
        assert message.startswith(
            f"container 'WebLabSide': error: its context broker {setting}: the MQTT broker at "
            f"127.0.0.1:{guarded_broker} did not accept the connection: Not authorized"
        ), message
        assert "its password in $ACORDCS_MQTT_PASSWORD" in message
        assert took < BOUND + 2
    # the refused connection closes, and nothing reconnects: no warning says it does
    assert not [r for r in caplog.records if "reconnecting" in r.getMessage()], caplog.text
    monkeypatch.setenv("ACORDCS_MQTT_PASSWORD", "right")
    open_broker(BrokerSetting("127.0.0.1", guarded_broker, "lab"), "WebLabSide", token=None,
                timeout=BOUND).close()  # fmt: skip


def test_no_broker_at_the_port_is_said_at_once() -> None:
    port = free_port()  # nothing listens there
    message, took = refused(BrokerSetting("127.0.0.1", port))
    assert message.startswith(
        f"container 'WebLabSide': error: its context broker mqtt://127.0.0.1:{port}: cannot reach "
        f"the MQTT broker at 127.0.0.1:{port}: [Errno 111] Connection refused"
    ), message
    assert "start the broker there" in message
    assert took < BOUND


class Babbler:
    """A TCP server on loopback that answers each connection with ``reply`` (bytes, or nothing:
    None) and keeps it open, reading what comes."""

    def __init__(self, reply: bytes | None) -> None:
        self.reply = reply
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.connections: list[socket.socket] = []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self) -> None:
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            self.connections.append(conn)
            if self.reply is not None:
                conn.sendall(self.reply)

    def close(self) -> None:
        self.sock.close()
        for conn in self.connections:
            conn.close()


GARBAGE = b"HTTP/1.1 400 Bad Request\r\n\r\n" + bytes(range(256)) * 4


@pytest.mark.parametrize("reply", [GARBAGE, None], ids=["garbage", "silence"])
def test_a_broker_speaking_no_mqtt_is_said_within_the_timeout(reply: bytes | None) -> None:
    babbler = Babbler(reply)
    try:
        message, took = refused(BrokerSetting("127.0.0.1", babbler.port))
    finally:
        babbler.close()
    assert message.startswith(
        f"container 'WebLabSide': error: its context broker mqtt://127.0.0.1:{babbler.port}: the "
        f"MQTT broker at 127.0.0.1:{babbler.port} did not accept the connection: no CONNACK "
        f"within {BOUND} s"
    ), message
    assert "is not an MQTT broker" in message
    assert took < BOUND + 2


@pytest.mark.parametrize("reply", [GARBAGE, None], ids=["garbage", "silence"])
def test_a_remote_container_speaking_no_pyro_is_said_within_the_timeout(
    reply: bytes | None,
) -> None:
    babbler = Babbler(reply)
    connector = RemoteConnector(timeout=BOUND, token="t" * 32)
    uri = container_uri("WebLabSide", "127.0.0.1", babbler.port)
    start = time.monotonic()
    try:
        with pytest.raises((RemoteUnreachableError, RemoteTimeoutError)) as caught:
            connector.request(uri, "call", "Locomotion", "LocomotionPort", "move", [], {},
                              where="connection 'ControlLink' to Locomotion.LocomotionPort")  # fmt: skip
    finally:
        connector.close()
        babbler.close()
    took = time.monotonic() - start
    message = str(caught.value)
    assert message.startswith("connection 'ControlLink' to Locomotion.LocomotionPort: error: ")
    assert f"the remote container at {uri}: " in message, message
    assert took < BOUND + 2, took


def test_the_launcher_takes_the_broker_from_its_setting_and_says_a_bad_one(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("ACORDCS_CONTEXT", "mqtt://ctx.example.org/weblab")
    args = Launcher("weblab_app", "WebLabSide").parser().parse_args([])
    assert args.context == BrokerSetting("ctx.example.org", prefix="weblab")
    args = Launcher("weblab_app", "WebLabSide").parser().parse_args(["--context", "embedded"])
    assert args.context is None
    monkeypatch.setenv("ACORDCS_CONTEXT", "tcp://ctx.example.org")
    with pytest.raises(SystemExit) as stopped:
        Launcher("weblab_app", "WebLabSide").parser().parse_args([])
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert "argument --context: 'tcp://ctx.example.org' is not 'embedded' or mqtt://" in err, err
    assert err.rstrip().endswith("(the setting $ACORDCS_CONTEXT)"), err


def test_the_launcher_runs_a_broker_only_on_a_real_clock(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("ACORDCS_CONTEXT", raising=False)
    launcher = Launcher("weblab_app", "WebLabSide")
    with pytest.raises(SystemExit) as stopped:
        launcher.main(["--context", "mqtt://127.0.0.1", "--clock", "virtual"])
    assert stopped.value.code == 2
    assert "error: --context mqtt://127.0.0.1:1883 needs --clock real" in capsys.readouterr().err
