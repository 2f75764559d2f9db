"""The console's server and hub against bad and slow viewers: malformed, oversized, binary and
unknown messages are refused with a reason; control commands need the session's token; the
viewer cap turns the next connection away; a viewer that never reads costs the experiment nothing
and bounded memory; a failing experiment command is a message, not a crash."""

from __future__ import annotations

import json
import threading
import time

import pytest
from starlette.testclient import TestClient
from weblab_console.commands import MAX_MESSAGE, CommandError, parse
from weblab_console.server import STRIKES, create_app

from acordcs.console.fanout import EVENT, EVENTS_KEPT, ConsoleHub
from tests.support.services import wait_for

PROFILES = ("residential", "campus", "lan")


class Session:
    """A test double of the experiment: records what it is told, checks the token like the
    access service, and fails on demand."""

    profiles = PROFILES
    mode = "simulation"

    def __init__(self) -> None:
        self.calls: list[tuple] = []
        self.fail = False

    def describe(self) -> dict:
        return {"profiles": list(self.profiles), "mode": self.mode}

    def authorize(self, token: str) -> bool:
        return token == "s3cret"

    def start(self, profile: str, seed: int) -> None:
        if self.fail:
            raise RuntimeError("the robot is charging")
        self.calls.append(("start", profile, seed))

    def stop(self) -> None:
        self.calls.append(("stop",))

    def drive(self, speed: float, turn: float) -> None:
        self.calls.append(("drive", speed, turn))

    def release(self) -> None:
        self.calls.append(("release",))


BASE = "http://127.0.0.1:8765"  # the Host the console answers to (TestClient's default is not)
WS = "ws://127.0.0.1:8765/ws"


@pytest.fixture
def console():
    hub, session = ConsoleHub(max_viewers=4, max_watchers=2), Session()
    with TestClient(create_app(hub, session), base_url=BASE) as client:
        yield client, hub, session


def receive_until(ws, kind: str, limit: int = 50) -> dict:
    for _ in range(limit):
        message = ws.receive()
        if message.get("text") is None:
            continue
        data = json.loads(message["text"])
        if data["type"] == kind:
            return data
    raise AssertionError(f"no {kind!r} message")


# --------------------------------------------------------------------------------- commands
@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("", "not JSON"),
        ("[1, 2]", "not a JSON object"),
        ('{"cmd": "fly"}', "unknown command 'fly'"),
        (
            '{"cmd": "start", "profile": "moon"}',
            "'profile' must be one of residential, campus, lan",
        ),
        ('{"cmd": "start", "profile": "lan", "seed": -1}', "'seed' must be an integer"),
        ('{"cmd": "start", "profile": "lan", "seed": true}', "'seed' must be an integer"),
        ('{"cmd": "drive", "speed": 1e309, "turn": 0}', "'speed' must be a number"),
        ('{"cmd": "drive", "speed": 9000, "turn": 0}', "'speed' must be from 0 to 500"),
        ('{"cmd": "drive", "speed": "fast", "turn": 0}', "'speed' must be a number"),
        ('{"cmd": "auth", "token": ""}', "'token' must be a string of 1 to 128"),
        ("[" * 100_000, "refused: at most 4096"),
        ('{"cmd": "ping", "pad": "' + "x" * MAX_MESSAGE + '"}', "refused: at most 4096"),
        (b"\x00\x01", "binary messages are refused"),
    ],
)
def test_bad_messages_are_refused_with_a_reason(text, says):
    with pytest.raises(CommandError, match=says.replace("(", r"\(").replace(")", r"\)")):
        parse(text, PROFILES)


def test_deeply_nested_json_within_the_size_limit_is_refused_not_a_crash():
    with pytest.raises(CommandError, match=r"not a JSON object|not JSON"):
        parse("[" * 2000 + "]" * 2000, PROFILES)


def test_good_commands_are_read_with_their_types():
    assert parse('{"cmd": "drive", "speed": 80, "turn": -12.5}', PROFILES).args == {
        "speed": 80.0,
        "turn": -12.5,
    }
    start = parse('{"cmd": "start", "profile": "campus", "seed": 7}', PROFILES)
    assert (start.name, start.args) == ("start", {"profile": "campus", "seed": 7})
    assert parse('{"cmd": "ping"}', PROFILES).name == "ping"


# ---------------------------------------------------------------------------------- server
def test_the_page_and_its_module_are_served(console):
    client, _, _ = console
    page = client.get("/")
    assert (
        page.status_code == 200 and '<script type="module" src="/static/console.js">' in page.text
    )
    assert client.get("/static/console.js").status_code == 200
    status = client.get("/status").json()
    assert status["mode"] == "simulation"  # the experiment in this process, not an attached app
    assert status["panel_state"]["weblab"]["profiles"] == list(PROFILES)
    (panel,) = status["panels"]  # the WebLab's, on the console's page
    assert client.get(panel["script"]).status_code == 200
    assert client.get(panel["style"]).status_code == 200


def test_control_without_the_token_is_refused_and_with_it_reaches_the_experiment(console):
    client, _, session = console
    with client.websocket_connect(WS) as ws:
        assert receive_until(ws, "hello")["panel_state"]["weblab"]["profiles"] == list(PROFILES)
        ws.send_text(json.dumps({"cmd": "start", "profile": "lan", "seed": 1}))
        refused = receive_until(ws, "refused")
        assert "needs the session's token" in refused["why"]
        ws.send_text(json.dumps({"cmd": "auth", "token": "guess"}))
        assert "does not know this token" in receive_until(ws, "refused")["why"]
        assert session.calls == []
        ws.send_text(json.dumps({"cmd": "auth", "token": "s3cret"}))
        receive_until(ws, "authorized")
        ws.send_text(json.dumps({"cmd": "start", "profile": "lan", "seed": 1}))
        assert receive_until(ws, "done")["cmd"] == "start"
    assert session.calls == [("start", "lan", 1)]


def test_a_failing_experiment_command_is_told_to_the_viewer(console):
    client, _, session = console
    session.fail = True
    with client.websocket_connect(WS) as ws:
        ws.send_text(json.dumps({"cmd": "auth", "token": "s3cret"}))
        receive_until(ws, "authorized")
        ws.send_text(json.dumps({"cmd": "start", "profile": "lan", "seed": 1}))
        error = receive_until(ws, "error")
        assert error["why"] == "RuntimeError: the robot is charging"
        ws.send_text(json.dumps({"cmd": "ping"}))
        receive_until(ws, "pong")  # the connection goes on


def test_a_viewer_sending_garbage_is_closed_after_its_strikes(console):
    client, hub, _ = console
    with client.websocket_connect(WS) as ws:
        for _ in range(STRIKES):
            ws.send_text("garbage")
        closed = None
        for _ in range(STRIKES + 10):
            message = ws.receive()
            if message["type"] == "websocket.close":
                closed = message
                break
        assert closed is not None and closed["code"] == 1008
    assert wait_for(lambda: hub.viewers == 0)


HOLDER = ["acordcs", "acordcs.token.s3cret"]  # how the page presents the token


def test_the_viewer_cap_turns_the_next_connection_away(console):
    client, hub, _ = console
    opened = [client.websocket_connect(WS, subprotocols=HOLDER) for _ in range(hub.max_viewers)]
    sockets = [c.__enter__() for c in opened]
    try:
        for ws in sockets:
            receive_until(ws, "authorized")
        with client.websocket_connect(WS, subprotocols=HOLDER) as extra:
            refused = json.loads(extra.receive()["text"])
            assert refused["type"] == "refused"
            assert "maximum of 4 viewers holding the token" in refused["why"]
            assert extra.receive()["code"] == 1013
    finally:
        for c in opened:
            c.__exit__(None, None, None)
    assert wait_for(lambda: hub.viewers == 0)


def test_viewers_get_frames_as_binary_and_the_rest_as_json(console):
    client, hub, _ = console
    with client.websocket_connect(WS) as ws:
        receive_until(ws, "hello")
        hub.publish("frame:onboard", b"\xff\xd8jpeg")
        hub.publish("context", {"Control.cycleRate": 1.5})
        got = {}
        for _ in range(4):
            message = ws.receive()
            if message.get("bytes") is not None:
                got["frame"] = message["bytes"]
            elif json.loads(message["text"])["type"] == "context":
                got["context"] = json.loads(message["text"])["data"]
            if len(got) == 2:
                break
        assert got == {"frame": b"\x01\xff\xd8jpeg", "context": {"Control.cycleRate": 1.5}}


def test_frames_of_both_cameras_pending_go_as_one_message(console):
    client, hub, _ = console
    onboard, panoramic = b"\xff\xd8on" * 100, b"\xff\xd8pan" * 300
    hub.publish("frame:onboard", onboard)
    hub.publish("frame:panoramic", panoramic)  # a viewer joining now has both pending
    with client.websocket_connect(WS) as ws:
        message = ws.receive()
        while message.get("bytes") is None:
            message = ws.receive()
    raw = message["bytes"]
    assert raw[0] == 0  # several frames: camera, 4-byte length, JPEG, each
    frames, at = {}, 1
    while at < len(raw):
        length = int.from_bytes(raw[at + 1 : at + 5], "big")
        frames[raw[at]] = raw[at + 5 : at + 5 + length]
        at += 5 + length
    assert frames == {1: onboard, 2: panoramic} and at == len(raw)


# ------------------------------------------------------------------------------------- hub
def test_a_viewer_that_never_reads_costs_bounded_memory_and_sees_the_newest():
    hub = ConsoleHub()
    wakes = []
    _, box = hub.join(lambda: wakes.append(1))
    for i in range(10_000):
        hub.publish("frame:onboard", bytes([i % 256]) * 1000)
        hub.publish(EVENT, {"n": i})
    latest, events = hub.take(box)
    assert latest == {"frame:onboard": bytes([9999 % 256]) * 1000}
    assert len(events) == EVENTS_KEPT and events[-1] == {"n": 9999}
    assert box.replaced == 9999 and box.dropped == 10_000 - EVENTS_KEPT


def test_a_viewer_whose_wake_blocks_does_not_hold_the_publisher_for_the_others():
    # The server's wake only schedules; a wake that raised would be the viewer's bug, not ours.
    hub = ConsoleHub()
    got = []
    hub.join(lambda: got.append("a"))
    hub.join(lambda: got.append("b"))
    started = time.perf_counter()
    for _ in range(1000):
        hub.publish("state", {"t": 0})
    # Woken once each: a mailbox holding something already has its wake pending.
    assert got.count("a") == got.count("b") == 1
    assert time.perf_counter() - started < 5  # not a timing claim: a hang would fail the test


def test_a_viewer_is_woken_when_its_mailbox_gets_its_first_item_after_a_take():
    hub = ConsoleHub()
    wakes = []
    _, box = hub.join(lambda: wakes.append(1))
    hub.publish("state", {"t": 1})
    hub.publish(EVENT, {"kind": "start"})
    assert len(wakes) == 1
    assert hub.take(box) == ({"state": {"t": 1}}, [{"kind": "start"}])
    hub.publish(EVENT, {"kind": "stop"})
    hub.publish("state", {"t": 2})
    assert len(wakes) == 2
    assert hub.take(box) == ({"state": {"t": 2}}, [{"kind": "stop"}])


def test_a_late_viewer_gets_the_current_state_and_recent_events():
    hub = ConsoleHub()
    hub.publish("path", {"points": [[0, 0]]})
    hub.publish(EVENT, {"kind": "start"})
    _, box = hub.join(lambda: None)
    latest, events = hub.take(box)
    assert latest == {"path": {"points": [[0, 0]]}} and events == [{"kind": "start"}]


def test_publishing_from_many_threads_while_viewers_come_and_go():
    hub = ConsoleHub(max_viewers=8)
    stop = threading.Event()

    def churn() -> None:
        while not stop.is_set():
            joined = hub.join(lambda: None)
            if joined:
                hub.take(joined[1])
                hub.leave(joined[0])

    workers = [threading.Thread(target=churn) for _ in range(4)]
    for w in workers:
        w.start()
    for i in range(20_000):
        hub.publish("state" if i % 2 else EVENT, {"i": i})
    stop.set()
    for w in workers:
        w.join(10)
    assert hub.viewers == 0 and hub.published == 20_000
