"""A local process without the application's token cannot grow a container's log at will: its
refused Pyro5 handshakes (to the container's endpoint, its management or its observer
interface: one daemon) are logged on the 1st, 2nd, 4th, 8th... refusal only, naming the peer's
address and the running count, and counted in the management interface's ``status``. Also a
handshake that is not one (garbage, a peer gone before the answer) is counted, not logged with a
traceback. Issue 36 item 2: 3,000 refusals grew the log by 333 KB, each line naming
``<SocketConnection object at 0x...>`` instead of the peer."""

from __future__ import annotations

import re
import socket
import time

import pytest
from Pyro5 import protocol, serializers

from acordcs.runtime.connectors.remote import RemoteConnector
from acordcs.runtime.live.management_server import MANAGE_OBJECT
from acordcs.runtime.live.observer import OBSERVE_OBJECT
from tests.support.managed_container import served_house

TOKEN = "token-of-the-house"
REFUSALS = 3000
OBJECTS = ("acordcs.container.house", MANAGE_OBJECT.format("house"), OBSERVE_OBJECT.format("house"))


@pytest.fixture
def house(tmp_path):
    """The container ``house`` in a child process, its output in ``house.log``; yields (port,
    log path)."""
    with served_house(tmp_path / "house.log", TOKEN) as (_child, port):
        yield port, tmp_path / "house.log"


def handshake(token: str | None, obj: str) -> bytes:
    """The bytes of a Pyro5 connection handshake (serpent) presenting ``token`` for ``obj``."""
    serializer = serializers.serializers["serpent"]
    data = serializer.dumps({"handshake": token, "object": obj})
    return protocol.SendingMessage(
        protocol.MSG_CONNECT, 0, 1, serializer.serializer_id, data, annotations={}
    ).data


def knock(port: int, message: bytes, *, read: bool = True) -> None:
    """One connection: send ``message``, read the answer (unless ``read`` is false), close."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as sock:
        sock.sendall(message)
        if read:
            sock.recv(4096)


def status(port: int) -> dict:
    connector = RemoteConnector(timeout=10.0, token=TOKEN)
    try:
        uri = f"PYRO:{MANAGE_OBJECT.format('house')}@127.0.0.1:{port}"
        return connector.request(uri, "status", where="test")
    finally:
        connector.close()


def wait_until_counted(port: int, key: str, count: int) -> dict:
    """The status once it counts ``count`` refusals of kind ``key`` (the last connections'
    workers may still be answering when the client has its answer), within 20 s."""
    deadline = time.monotonic() + 20
    while True:
        found = status(port)
        if found["refused"][key] >= count or time.monotonic() > deadline:
            return found
        time.sleep(0.1)


def test_3000_refused_handshakes_grow_the_log_by_under_10_kb_and_are_counted(house):
    port, log = house
    messages = [handshake(t, o) for t in (None, "guess") for o in OBJECTS]
    before = log.stat().st_size
    started = time.monotonic()
    for i in range(REFUSALS):
        knock(port, messages[i % len(messages)])
        assert time.monotonic() - started < 120, f"{i} refusals took over 120 s"
    found = wait_until_counted(port, "wrong_token", REFUSALS)
    grown = log.stat().st_size - before
    text = log.read_text()
    assert grown < 10_000, f"the log grew by {grown} bytes:\n{text[-3000:]}"
    assert found["refused"]["wrong_token"] == REFUSALS
    lines = [line for line in text.splitlines() if "refused a connection" in line]
    # the 1st, 2nd, 4th... 2048th: 12 lines, each naming the peer and the count so far
    assert len(lines) == 12, lines
    assert all(re.search(r"from 127\.0\.0\.1:\d+", line) for line in lines), lines
    assert "(2048 refused so far" in lines[-1] and "SocketConnection" not in text
    assert "Traceback" not in text
    # the application's own processes still get in
    assert status(port)["container"] == "house"


def test_garbage_and_peers_gone_early_leave_no_traceback_and_no_flood(house):
    """What is not a Pyro5 handshake never reaches the token check: Pyro5 drops it (and logs it
    at debug level only); the log stays bounded and only token refusals are counted."""
    port, log = house
    before = log.stat().st_size
    for _ in range(200):
        knock(port, b"GET / HTTP/1.0\r\n\r\n" + b"x" * 100)
    for _ in range(200):  # the handshake, and gone before the refusal is sent
        with socket.create_connection(("127.0.0.1", port), timeout=5) as sock:
            sock.setsockopt(
                socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00"
            )
            sock.sendall(handshake("guess", OBJECTS[0]))
    found = wait_until_counted(port, "wrong_token", 1)
    text = log.read_text()[before:]
    assert set(found["refused"]) == {"wrong_token"}, found["refused"]
    assert found["refused"]["wrong_token"] <= 200
    assert "Traceback" not in text and len(text) < 10_000, text[-3000:]
