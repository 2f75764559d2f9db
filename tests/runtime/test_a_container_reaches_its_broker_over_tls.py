"""A container's context broker over TLS (``mqtts://``, issue 33's brokers on other machines):
the broker's certificate verified against ``$ACORDCS_MQTT_CA`` and its name against the address;
each way it can go wrong said at start, naming the container and the broker, never a hang."""

from __future__ import annotations

import getpass
import time
from pathlib import Path

import pytest

from acordcs.runtime.broker_setting import CA_ENV, BrokerSetting, open_broker, parse_context
from acordcs.runtime.context import Notification
from acordcs.runtime.errors import ConfigurationError
from tests.support.services import Broker, free_port, wait_for
from tests.support.tls_certs import make_server_certificate

TIMEOUT = 3.0


@pytest.fixture(scope="module")
def tls_broker(tmp_path_factory: pytest.TempPathFactory):
    """mosquitto with a plain listener (``port``) and a TLS one (``tls_port``), its certificate
    signed by a CA of the test's own (``ca``) for 127.0.0.1 only; ``other_ca``: a CA that did not
    sign it."""
    tmp = tmp_path_factory.mktemp("tls-broker")
    broker = Broker(tmp)  # skips (or fails in CI) without mosquitto
    made = make_server_certificate(tmp / "etc", san="IP:127.0.0.1", name="broker")
    other = make_server_certificate(tmp / "other", san="IP:127.0.0.1", name="stranger")
    broker.tls_port = free_port()
    with broker.config.open("a") as config:
        config.write(
            f"listener {broker.tls_port} 127.0.0.1\n"
            f"certfile {made.certificate}\nkeyfile {made.key}\n"
            # mosquitto started as root drops to user mosquitto, who cannot read the test's files
            f"user {getpass.getuser()}\n"
        )
    broker.start()
    broker.ca, broker.other_ca = made.ca, other.ca
    yield broker
    broker.stop()


def opened(address: str, container: str = "Lab"):
    return open_broker(parse_context(address), container, token=None, timeout=TIMEOUT)


def refusal(address: str, monkeypatch: pytest.MonkeyPatch, ca: Path | str | None) -> str:
    """What the container is told at start, checked to come within the connect timeout."""
    if ca is None:
        monkeypatch.delenv(CA_ENV, raising=False)
    else:
        monkeypatch.setenv(CA_ENV, str(ca))
    started = time.monotonic()
    with pytest.raises(ConfigurationError) as caught:
        opened(address)
    assert time.monotonic() - started < TIMEOUT + 2
    said = str(caught.value)
    assert "container 'Lab'" in said, said
    return said


def test_an_mqtts_address_means_tls_and_port_8883_unless_given():
    assert parse_context("mqtts://robot@broker.lab") == BrokerSetting(
        "broker.lab", 8883, "robot", "acordcs/ctx", tls=True
    )
    assert str(parse_context("mqtts://broker.lab:9883/weblab")) == "mqtts://broker.lab:9883/weblab"
    assert parse_context("mqtt://broker.lab") == BrokerSetting("broker.lab", 1883)
    with pytest.raises(ValueError, match=r"mqtts:// over TLS"):
        parse_context("tls://broker.lab")


def test_a_container_shares_context_through_a_broker_over_tls(tls_broker, monkeypatch):
    monkeypatch.setenv(CA_ENV, str(tls_broker.ca))
    address = f"mqtts://127.0.0.1:{tls_broker.tls_port}"
    lab, user = opened(address, "Lab"), opened(address, "User")
    try:
        seen: list[str] = []

        def on_change(note: Notification) -> None:
            seen.append(note.nodes[0].text)

        user.subscribe(on_change, "/robot/speed", publisher="lab")
        lab.publish("lab", b"<robot><speed>42</speed></robot>")
        assert wait_for(lambda: seen == ["42"]), seen
    finally:
        user.close()
        lab.close()


def test_a_certificate_signed_by_another_ca_is_refused_at_start(tls_broker, monkeypatch):
    said = refusal(f"mqtts://127.0.0.1:{tls_broker.tls_port}", monkeypatch, tls_broker.other_ca)
    assert f"mqtts://127.0.0.1:{tls_broker.tls_port}" in said
    assert "certificate verify failed" in said and CA_ENV in said


def test_without_a_ca_file_the_systems_cas_do_not_know_the_broker(tls_broker, monkeypatch):
    said = refusal(f"mqtts://127.0.0.1:{tls_broker.tls_port}", monkeypatch, None)
    assert "certificate verify failed" in said and CA_ENV in said


def test_a_name_the_certificate_does_not_hold_is_refused(tls_broker, monkeypatch):
    # the certificate holds 127.0.0.1; "localhost" reaches the same listener under another name
    said = refusal(f"mqtts://localhost:{tls_broker.tls_port}", monkeypatch, tls_broker.ca)
    assert "localhost" in said and "certificate" in said and "name the host" in said


def test_tls_to_a_port_without_tls_says_so(tls_broker, monkeypatch):
    said = refusal(f"mqtts://127.0.0.1:{tls_broker.port}", monkeypatch, tls_broker.ca)
    assert "the broker's TLS listener" in said


def test_a_ca_file_that_cannot_be_read_is_said_before_connecting(tls_broker, monkeypatch, tmp_path):
    missing = tmp_path / "no-such-ca.pem"
    said = refusal(f"mqtts://127.0.0.1:{tls_broker.tls_port}", monkeypatch, missing)
    assert str(missing) in said and CA_ENV in said


def test_plain_mqtt_to_the_tls_port_is_not_taken_for_a_broker(tls_broker, monkeypatch):
    said = refusal(f"mqtt://127.0.0.1:{tls_broker.tls_port}", monkeypatch, None)
    assert f"mqtt://127.0.0.1:{tls_broker.tls_port}" in said and "needs mqtts://" in said


def test_the_launcher_takes_an_mqtts_broker_from_its_setting(monkeypatch):
    from acordcs.runtime.launcher import Launcher

    monkeypatch.setenv("ACORDCS_CONTEXT", "mqtts://lab@ctx.example.org/weblab")
    args = Launcher("weblab_app", "WebLabSide").parser().parse_args([])
    assert args.context == BrokerSetting("ctx.example.org", 8883, "lab", "weblab", tls=True)
    assert str(args.context) == "mqtts://lab@ctx.example.org:8883/weblab"
