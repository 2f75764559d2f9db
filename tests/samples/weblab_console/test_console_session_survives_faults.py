"""The console's session over the real experiment, served by uvicorn on a loopback port, with
WebSocket clients: the access service decides the token; stopping the experiment under open
pages, and the experiment raising, are messages to the pages, never a crash of the server; a
viewer opening 100 connections gets the cap's worth and a clear refusal for the rest; a frame over
uvicorn's limit closes that socket only; manual control overrides the Navigator through its port."""

from __future__ import annotations

import contextlib
import json
import time

import pytest
from weblab_console.serving import serving
from weblab_console.session import ConsoleSession, SessionError

from acordcs.console.fanout import ConsoleHub

websockets_sync = pytest.importorskip("websockets.sync.client")
ConnectionClosed = pytest.importorskip("websockets.exceptions").ConnectionClosed

TOKEN = "fault-test-token"


@pytest.fixture
def console(weblab_app):
    hub = ConsoleHub(max_viewers=32)
    session = ConsoleSession(hub, TOKEN, speed=20.0)
    with serving(hub, session) as url:
        yield url.replace("http://", "ws://") + "/ws", hub, session


def messages(ws, until, timeout: float = 20.0) -> list[dict]:
    """Text messages received until ``until(message)`` holds (binary frames skipped)."""
    seen: list[dict] = []
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        raw = ws.recv(timeout=deadline - time.monotonic())
        if isinstance(raw, bytes):
            continue
        decoded = json.loads(raw)
        # Several pending messages come as one array, in order.
        for message in decoded if isinstance(decoded, list) else [decoded]:
            seen.append(message)
            if until(message):
                return seen
    raise AssertionError(f"never came; last messages: {seen[-5:]}")


def seen_all(ws, *conditions) -> list[dict]:
    """The first message meeting each condition, in any order (a viewer's mailbox sends the
    newest state before the events of the same moment)."""
    found: dict[int, dict] = {}

    def done(m: dict) -> bool:
        for i, condition in enumerate(conditions):
            if i not in found and condition(m):
                found[i] = m
        return len(found) == len(conditions)

    messages(ws, done)
    return [found[i] for i in range(len(conditions))]


def event(kind: str):
    return lambda m: m["type"] == "event" and m["data"].get("what", m["data"]["kind"]) == kind


@contextlib.contextmanager
def authorized(url: str):
    with websockets_sync.connect(url) as ws:
        ws.send(json.dumps({"cmd": "auth", "token": TOKEN}))
        assert (
            messages(ws, lambda m: m["type"] in ("authorized", "refused"))[-1]["type"]
            == "authorized"
        )
        yield ws


def test_the_access_service_decides_the_token_idle_and_running(console):
    _url, _hub, session = console
    assert session.authorize(TOKEN) and not session.authorize("guess")
    session.start("LAN", 1)
    assert session.authorize(TOKEN) and not session.authorize(TOKEN + "x")


def test_stopping_the_experiment_under_open_pages_tells_them_and_the_server_goes_on(console):
    url, _hub, session = console
    with authorized(url) as a, websockets_sync.connect(url) as b:
        a.send(json.dumps({"cmd": "start", "profile": "campus", "seed": 2}))
        messages(a, lambda m: m["type"] == "done" and m["cmd"] == "start")
        messages(b, lambda m: m["type"] == "state" and m["data"]["running"])
        session.stop()  # the application stops under both pages
        for ws in (a, b):
            seen_all(ws, event("stop"), lambda m: m["type"] == "state" and not m["data"]["running"])
        a.send(json.dumps({"cmd": "drive", "speed": 50, "turn": 0}))
        reply = messages(a, lambda m: m["type"] in ("error", "done"))[-1]
        assert reply["type"] == "error" and "no experiment is running" in reply["why"]
        a.send(json.dumps({"cmd": "start", "profile": "LAN", "seed": 3}))  # and again
        messages(
            a, lambda m: m["type"] == "state" and m["data"]["running"] and m["data"]["seed"] == 3
        )
    assert not session.running or session.stop() is None


def test_the_experiment_raising_is_a_fault_event_not_a_crash(console, monkeypatch):
    from weblab_sim import detector

    url, _hub, session = console
    calls = {"n": 0}
    real = detector.find_stripe

    def failing(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] > 5:
            raise RuntimeError("the camera driver crashed (test)")
        return real(*args, **kwargs)

    monkeypatch.setattr(detector, "find_stripe", failing)
    with authorized(url) as ws:
        ws.send(json.dumps({"cmd": "start", "profile": "LAN", "seed": 1}))
        fault, _state = seen_all(
            ws, event("fault"), lambda m: m["type"] == "state" and not m["data"]["running"]
        )
        assert "the camera driver crashed (test)" in fault["data"]["text"]
        ws.send(json.dumps({"cmd": "ping"}))
        messages(ws, lambda m: m["type"] == "pong")
    assert not session.running
    with pytest.raises(SessionError, match="no experiment is running"):
        session.drive(10.0, 0.0)


def test_a_viewer_opening_100_connections_gets_the_cap_and_a_refusal_for_the_rest(console):
    url, hub, _session = console
    opened, refused = 0, 0
    with contextlib.ExitStack() as stack:
        for _ in range(100):
            ws = stack.enter_context(websockets_sync.connect(url))
            first = json.loads(ws.recv(timeout=10))
            if first["type"] == "refused":
                assert "maximum of 8 viewers without the token" in first["why"]
                with pytest.raises(ConnectionClosed):  # closed by the server: try again later
                    ws.recv(timeout=10)
                assert ws.close_code == 1013
                refused += 1
            else:
                opened += 1
        assert (opened, refused) == (8, 92)
        assert hub.viewers == 8
        # the connections without the token never take the token holder's place
        holder = stack.enter_context(
            websockets_sync.connect(url, subprotocols=["acordcs", f"acordcs.token.{TOKEN}"])
        )
        assert messages(holder, lambda m: m["type"] in ("authorized", "refused"))[-1] == {
            "type": "authorized"
        }
        assert hub.viewers == 9
    deadline = time.monotonic() + 10
    while hub.viewers and time.monotonic() < deadline:
        time.sleep(0.05)
    assert hub.viewers == 0
    with websockets_sync.connect(url) as ws:  # room again
        assert json.loads(ws.recv(timeout=10))["type"] != "refused"


def test_a_frame_over_the_servers_limit_closes_that_socket_only(console):
    url, _hub, _session = console
    with websockets_sync.connect(url) as good, websockets_sync.connect(url, max_size=None) as bad:
        bad.send("x" * 100_000)
        with pytest.raises(ConnectionClosed):
            while True:
                bad.recv(timeout=10)
        assert bad.close_code == 1009  # message too big
        good.send(json.dumps({"cmd": "ping"}))
        messages(good, lambda m: m["type"] == "pong")


def test_manual_control_overrides_the_navigator_through_its_port(console):
    url, _hub, session = console
    session.set_speed(0)  # as fast as it runs: the check is about what happens, not when
    with authorized(url) as ws:
        ws.send(json.dumps({"cmd": "start", "profile": "LAN", "seed": 4}))
        messages(ws, lambda m: m["type"] == "done")
        ws.send(json.dumps({"cmd": "drive", "speed": 120, "turn": 30}))
        states = messages(
            ws,
            lambda m: (
                m["type"] == "state" and m["data"]["driver"] == "manual" and m["data"]["speed"] > 0
            ),
        )
        assert states[-1]["data"]["running"]
        # The Control monitor saw the console's command: the angle is the manual turn (the
        # console's page has it from the container's observer).
        context = messages(
            ws,
            lambda m: (
                m["type"] == "event"
                and m["data"]["kind"] == "monitor"
                and m["data"]["element"] == "Control"
                and m["data"]["values"].get("angle") == 30.0
            ),
        )
        assert context
        ws.send(json.dumps({"cmd": "release"}))
        messages(ws, lambda m: m["type"] == "state" and m["data"]["driver"] == "navigator")
