"""The MQTT context provider against hostile clients of the broker (issue 14, items 3 and 4), and
the shipped secure mosquitto configuration (deploy/mosquitto), on a real mosquitto on loopback."""

from __future__ import annotations

import getpass
import logging
import shutil
import subprocess
import threading
from pathlib import Path

import paho.mqtt.client as mqtt
import pytest
from paho.mqtt.enums import CallbackAPIVersion

from acordcs.runtime.context import MqttContextProvider, Notification, publisher_topic
from tests.support.services import Broker, free_port, wait_for
from tests.support.tls_certs import make_server_certificate

pytestmark = pytest.mark.service

DEPLOY = Path(__file__).parents[2] / "deploy" / "mosquitto"
KEY = "an-application-key-of-32-bytes!!"


class Inbox:
    def __init__(self) -> None:
        self.notes: list[Notification] = []
        self.lock = threading.Lock()

    def __call__(self, note: Notification) -> None:
        with self.lock:
            self.notes.append(note)

    def texts(self) -> list[str]:
        with self.lock:
            return [n.nodes[0].text for n in self.notes]


@pytest.fixture
def broker(tmp_path: Path):
    server = Broker(tmp_path)
    server.start()
    yield server
    server.stop()


@pytest.fixture
def clients(broker: Broker):
    made: list[MqttContextProvider] = []

    def make(**options) -> MqttContextProvider:
        client = MqttContextProvider("127.0.0.1", options.pop("port", broker.port), **options)
        made.append(client)
        return client

    yield make
    for client in made:
        client.close()


class Raw:
    """A bare paho client: the attacker."""

    def __init__(self, port: int, **login: str) -> None:
        self.client = mqtt.Client(CallbackAPIVersion.VERSION2, protocol=mqtt.MQTTv311)
        if login:
            self.client.username_pw_set(login["username"], login["password"])
        self.retained: dict[str, bytes] = {}
        self.client.on_message = lambda c, u, m: self.retained.__setitem__(m.topic, m.payload)
        self.client.connect("127.0.0.1", port)
        self.client.loop_start()

    def send(self, topic: str, payload: bytes) -> None:
        self.client.publish(topic, payload, qos=1, retain=True).wait_for_publish(5)

    def read(self, topic: str) -> bytes:
        self.client.subscribe(topic, qos=1)
        assert wait_for(lambda: topic in self.retained)
        return self.retained[topic]

    def close(self) -> None:
        self.client.disconnect()
        self.client.loop_stop()


def doc(n: int) -> str:
    return f"<robot><pos>{n}</pos></robot>"


def test_a_forged_huge_sequence_number_does_not_silence_a_publisher(broker, clients, caplog):
    robot, console = clients(), clients(mirror=False)
    inbox = Inbox()
    console.subscribe(inbox, "/robot/pos", publisher="robot")
    robot.publish("robot", doc(1))
    assert wait_for(lambda: inbox.texts() == ["1"])
    attacker = Raw(broker.port)
    try:
        topic = publisher_topic("robot")
        epoch = attacker.read(topic).split(b" ")[1]  # readable from the retained payload
        with caplog.at_level(logging.WARNING, logger="acordcs.runtime.context.mqtt"):
            attacker.send(topic, b"ACX1 %s 999999999999\n<robot><pos>666</pos></robot>" % epoch)
            assert wait_for(lambda: console.stats()["implausible"] == 1)
        assert "a jump over max_seq_jump" in caplog.text
        robot.publish("robot", doc(2))
        robot.publish("robot", doc(3))
        assert wait_for(lambda: inbox.texts() == ["1", "2", "3"]), inbox.texts()
    finally:
        attacker.close()


def test_a_forged_plausible_number_is_overcome_after_a_few_documents(broker, clients):
    robot, console = clients(), clients(mirror=False)
    inbox = Inbox()
    console.subscribe(inbox, "/robot/pos", publisher="robot")
    robot.publish("robot", doc(1))
    assert wait_for(lambda: inbox.texts() == ["1"])
    attacker = Raw(broker.port)
    try:
        topic = publisher_topic("robot")
        epoch = attacker.read(topic).split(b" ")[1]
        attacker.send(topic, b"ACX1 %s 50\n<robot><pos>666</pos></robot>" % epoch)
        assert wait_for(lambda: inbox.texts() == ["1", "666"])
        for n in range(2, 7):
            robot.publish("robot", doc(n))
        # the forged jump counted 2-49 lost; 2 and 3 come late (delivered, not the latest), the
        # third resynchronises the publisher: 5-49 are to come, no longer lost; nothing is
        # dropped (before a late document was told from a repeat, 2 and 3 were)
        assert wait_for(lambda: inbox.texts()[-1] == "6"), inbox.texts()
        assert inbox.texts() == ["1", "666", "2", "3", "4", "5", "6"]
        stats = console.stats()
        assert (stats["resynchronised"], stats["late"], stats["lost"]) == (1, 3, 0), stats
        assert stats["duplicates"] == 0
        assert console.latest("robot")[0] == 6
    finally:
        attacker.close()


def test_with_a_payload_key_only_signed_documents_are_taken(broker, clients):
    robot, console = clients(payload_key=KEY), clients(mirror=False, payload_key=KEY)
    inbox = Inbox()
    console.subscribe(inbox, "/robot/pos", publisher="robot")
    robot.publish("robot", doc(1))
    assert wait_for(lambda: inbox.texts() == ["1"])
    attacker = Raw(broker.port)
    try:
        topic = publisher_topic("robot")
        header = attacker.read(topic).split(b"\n", 1)[0].split(b" ")
        assert header[0] == b"ACX2" and len(header[3]) == 64
        body = b"<robot><pos>666</pos></robot>"
        attacker.send(topic, b"ACX1 %s 2\n%s" % (header[1], body))  # unsigned
        attacker.send(topic, b"ACX2 %s 2 %s\n%s" % (header[1], header[3], body))  # replayed MAC
        # another client without the key is not an acceptable signer either
        clients(payload_key="another-key-of-the-wrong-app").publish("robot", doc(99))
        assert wait_for(lambda: console.stats()["forged"] == 3)
        robot.publish("robot", doc(2))
        assert wait_for(lambda: inbox.texts() == ["1", "2"]), inbox.texts()
    finally:
        attacker.close()


def test_publishers_beyond_the_cap_are_ignored_with_a_diagnostic(clients, caplog):
    console = clients(max_publishers=3)
    flood = clients()
    with caplog.at_level(logging.WARNING, logger="acordcs.runtime.context.mqtt"):
        for n in range(8):
            flood.publish(f"p{n}", doc(n))
        assert wait_for(lambda: console.stats()["refused_publishers"] == 5)
    assert len(console.publishers()) == 3
    assert "max_publishers=3" in caplog.text and "raise max_publishers" in caplog.text
    # a publisher already kept goes on; a retired one frees its place
    kept = console.publishers()[0]
    flood.retire(kept)
    assert wait_for(lambda: kept not in console.publishers())
    flood.publish("newcomer", doc(1))
    assert wait_for(lambda: "newcomer" in console.publishers())


# -- the shipped secure configuration ----------------------------------------------------------------
@pytest.fixture
def secure_broker(tmp_path: Path):
    """mosquitto with deploy/mosquitto/acordcs.conf and acordcs.acl, paths and ports moved to
    ``tmp_path`` and free loopback ports; users robot1 and console (password = name + '-pw')."""
    passwd_tool = shutil.which("mosquitto_passwd") or "/usr/bin/mosquitto_passwd"
    server = Broker(tmp_path)  # skips (or fails in CI) without mosquitto
    etc = tmp_path / "etc"
    etc.mkdir()
    shutil.copy(DEPLOY / "acordcs.acl", etc / "acordcs.acl")
    for user in ("robot1", "console"):
        subprocess.run(
            [passwd_tool, "-b", *(["-c"] if user == "robot1" else []), str(etc / "passwd"),
             user, f"{user}-pw"],
            check=True, capture_output=True, timeout=30,
        )  # fmt: skip
    made = make_server_certificate(etc, name="server")  # the paths acordcs.conf names
    tls_port = free_port()
    text = (DEPLOY / "acordcs.conf").read_text()
    text = text.replace("/etc/mosquitto/acordcs/", f"{etc}/").replace(
        "/var/lib/mosquitto/", f"{tmp_path}/"
    )
    text = text.replace("listener 1883 127.0.0.1", f"listener {server.port} 127.0.0.1")
    text = text.replace("listener 8883\n", f"listener {tls_port} 127.0.0.1\n")
    assert str(server.port) in text and str(tls_port) in text
    # mosquitto started as root drops to user mosquitto, who cannot read the test's files
    user = f"user {getpass.getuser()}\n"
    server.config.write_text(text + f"log_dest file {server.log}\n" + user)
    server.start()
    server.tls_port = tls_port
    server.ca = str(made.ca)
    yield server
    server.stop()


def test_shipped_configuration_shows_the_broker_limits() -> None:
    text = (DEPLOY / "acordcs.conf").read_text()
    for line in ("allow_anonymous false", "max_packet_size", "memory_limit", "acl_file"):
        assert line in text
    assert "pattern write acordcs/ctx/%u" in (DEPLOY / "acordcs.acl").read_text()


def test_secure_broker_refuses_strangers_and_keeps_publishers_to_their_topic(
    secure_broker, clients
):
    from acordcs.runtime.context import ContextError

    with pytest.raises(ContextError, match="did not accept the connection"):
        clients(port=secure_broker.port, connect_timeout=3)  # anonymous
    login = {"tls_ca_certs": secure_broker.ca, "port": secure_broker.tls_port}
    robot = clients(username="robot1", password="robot1-pw", **login)
    console = clients(username="console", password="console-pw", mirror=False, **login)
    inbox = Inbox()
    console.subscribe(inbox, "/robot/pos")
    robot.publish("console", doc(666))  # not its topic: the broker drops it
    robot.publish("robot1", doc(1))
    assert wait_for(lambda: inbox.texts() == ["1"]), inbox.texts()
    assert [n.publisher for n in inbox.notes] == ["robot1"]
    assert console.latest("console") is None


def test_a_5000_digit_sequence_number_is_malformed_without_a_traceback(broker, clients, caplog):
    console = clients()
    attacker = Raw(broker.port)
    try:
        with caplog.at_level(logging.WARNING, logger="acordcs.runtime.context.mqtt"):
            attacker.send(publisher_topic("robot"), b"ACX1 abcd " + b"9" * 5000 + b"\n<r/>")
            assert wait_for(lambda: console.stats()["malformed"] == 1)
        assert "not an acordcs context document" in caplog.text
        assert not any(r.exc_info for r in caplog.records)
        assert console.publishers() == []
    finally:
        attacker.close()
