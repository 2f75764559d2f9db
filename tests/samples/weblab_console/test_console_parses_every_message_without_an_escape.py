"""Every message a viewer may send, with hostile values in every field, is answered and never
escapes the console's handling (issue 36, item 3: a 401-digit speed raised ``OverflowError`` in
``math.isfinite`` before the token check, so no strike was counted, the connection died with
1006 and a 4 KB traceback went to the log each time).

The corpus: for each command the console accepts (``auth``, ``start``, ``stop``, ``drive``,
``release``, ``ping``: :mod:`weblab_console.commands`) and each of its fields (and an extra one),
huge integers, ``1e309``, ``NaN``, ``Infinity``, deep JSON, wrong types, missing fields, huge and
odd strings; and whole messages of the wrong shape. Each is sent by a viewer without the token
and by one holding it, followed by a ``ping``: the message must be answered before the ``pong``
(refused, or carried out when it is valid after all), every refusal is a strike, and nothing is
logged but the bounded refusal lines, never a traceback. Then the same over a real uvicorn
server and a real WebSocket client, where an escape closes the connection (1006) and logs a
traceback."""

from __future__ import annotations

import json
import logging
import math
import time

import pytest
from starlette.testclient import TestClient
from weblab_console import server as console_server
from weblab_console.commands import MAX_MESSAGE, MAX_SPEED, MAX_TURN
from weblab_console.server import STRIKES, create_app
from weblab_console.serving import serving

from acordcs.console import web_app
from acordcs.console.fanout import ConsoleHub
from tests.samples.weblab_console.test_console_server_holds_under_bad_viewers import (
    BASE,
    HOLDER,
    PROFILES,
    WS,
    Session,
)

websockets_sync = pytest.importorskip("websockets.sync.client")

HUGE = "9" * 401
HOSTILE_VALUES = [
    HUGE,
    "-" + HUGE,
    "1" + "0" * 4000,  # about as long as a message may be
    "1e309",
    "-1e309",
    "1e-400",  # 0.0: valid where 0 is
    "NaN",
    "Infinity",
    "-Infinity",
    "2147483648",
    "-1",
    "0.5",
    "1.0",
    "true",
    "false",
    "null",
    '""',
    '"' + "x" * 3900 + '"',
    '"\\ud800"',  # a lone surrogate
    '"\\u0000"',
    '"lan\\u0000"',
    "[]",
    "{}",
    "[1, 2]",
    '{"a": 1}',
    "[" * 400 + "]" * 400,
    '{"a": ' * 300 + "1" + "}" * 300,
]
COMMANDS = {  # each command, valid, and the fields it reads
    "auth": ({"cmd": "auth", "token": "s3cret"}, ["token"]),
    "start": ({"cmd": "start", "profile": "lan", "seed": 1}, ["profile", "seed"]),
    "stop": ({"cmd": "stop"}, []),
    "drive": ({"cmd": "drive", "speed": 80, "turn": -10}, ["speed", "turn"]),
    "release": ({"cmd": "release"}, []),
    "ping": ({"cmd": "ping"}, []),
}
WHOLE = [  # messages of the wrong shape
    "",
    " ",
    "null",
    "[]",
    '"cmd"',
    HUGE,
    "1e309",
    "NaN",
    "[" * 4000,
    "[" * 2000 + "]" * 2000,
    '{"cmd": ' * 1000 + "1" + "}" * 1000,
    '{"cmd": "drive", "speed": 1, "turn": 1, "speed": ' + HUGE + "}",  # duplicate key
    '{"cmd": "' + "x" * (MAX_MESSAGE - 10) + '"}',
    '{"cmd": "ping", "pad": "' + "x" * MAX_MESSAGE + '"}',  # over the size limit
    '{"cmd": "ping"',  # not closed
    "\ufeff{}",
]


def corpus() -> list[tuple[str, str]]:
    """(what, message text): every field of every command with every hostile value, each field
    missing, an extra field, and the wrong shapes."""
    found: list[tuple[str, str]] = []
    for name, (valid, fields) in COMMANDS.items():
        for key in [*fields, "cmd", "extra"]:
            for value in HOSTILE_VALUES:
                text = json.dumps({**valid, key: "@@"}).replace('"@@"', value)
                found.append((f"{name}.{key}={value[:20]}", text))
        for key in fields:
            found.append((f"{name} without {key}", json.dumps(dict(valid) | {key: None})))
            found.append(
                (f"{name} without {key}", json.dumps({k: v for k, v in valid.items() if k != key}))
            )
    found += [(f"whole {text[:20]!r}", text) for text in WHOLE]
    return found


def answers(ws) -> list[dict]:
    """The messages a viewer gets until its ``pong`` (several may come as one array)."""
    got: list[dict] = []
    for _ in range(50):
        message = ws.receive()
        if message["type"] == "websocket.close":
            raise AssertionError(f"closed ({message.get('code')}) after {got}")
        if message.get("text") is None:
            continue
        decoded = json.loads(message["text"])
        for item in decoded if isinstance(decoded, list) else [decoded]:
            if item["type"] == "pong":
                return got
            if item["type"] in ("refused", "error", "done", "authorized"):
                got.append(item)
    raise AssertionError(f"no pong; got {got}")


def test_every_message_kind_with_hostile_values_is_answered_and_counted(caplog):
    caplog.set_level(logging.WARNING)
    hub, session = ConsoleHub(max_viewers=4, max_watchers=4), Session()
    messages = corpus()
    refused = 0
    with TestClient(create_app(hub, session), base_url=BASE) as client:
        for holder in (False, True):
            for start in range(0, len(messages), STRIKES // 2):
                batch = messages[start : start + STRIKES // 2]
                protocols = HOLDER if holder else ["acordcs"]
                with client.websocket_connect(WS, subprotocols=protocols) as ws:
                    ws.send_text('{"cmd": "ping"}')
                    answers(ws)  # hello (and authorized), then pong
                    for what, text in batch:
                        ws.send_text(text)
                        ws.send_text('{"cmd": "ping"}')
                        got = answers(ws)
                        if what.startswith("ping.extra"):  # a ping after all: its own pong
                            assert got == [] and answers(ws) == [], (what, got)
                            continue
                        assert len(got) == 1, (what, got)
                        if got and got[0]["type"] == "refused":
                            refused += 1
                            assert got[0]["why"] and got[0]["todo"], (what, got)
                            assert len(json.dumps(got[0])) < 1000, (what, got)
        counts = client.get("/status").json()["refused"]
    # a refusal is a strike: counted as a refused message (or a wrong token)
    assert counts["message"] + counts["token"] == refused, counts
    assert counts["fault"] == 0 and counts["closed"] == 0, counts
    # what reached the experiment is of the types and ranges the commands promise
    for call in session.calls:
        if call[0] == "drive":
            _, speed, turn = call
            assert type(speed) is float and type(turn) is float
            assert 0 <= speed <= MAX_SPEED and -MAX_TURN <= turn <= MAX_TURN
            assert math.isfinite(speed) and math.isfinite(turn)
        if call[0] == "start":
            _, profile, seed = call
            assert profile in PROFILES and type(seed) is int and 0 <= seed < 2**31
    assert not [r for r in caplog.records if r.exc_info or r.levelno >= logging.ERROR]
    logged = [r.getMessage() for r in caplog.records]
    assert "Traceback" not in caplog.text
    # bounded: the 1st, 2nd, 4th... refusal of each kind only
    for kind, count in counts.items():
        lines = [m for m in logged if f"({_reason(kind)}" in m or f": {_reason(kind)}" in m]
        assert len(lines) <= max(1, count.bit_length()), (kind, count, lines)


def _reason(kind: str) -> str:
    return web_app.REFUSED[kind]


def test_a_401_digit_speed_is_a_strike_before_the_token_check():
    hub, session = ConsoleHub(), Session()
    drive = '{"cmd": "drive", "speed": ' + HUGE + ', "turn": 0}'
    with TestClient(create_app(hub, session), base_url=BASE) as client:
        with client.websocket_connect(WS) as ws:
            for _ in range(STRIKES):
                ws.send_text(drive)
                message = ws.receive()
                while message.get("text") is None or '"refused"' not in message["text"]:
                    message = ws.receive()
                why = json.loads(message["text"])["why"]
                assert why == "'speed' must be from 0 to 500, not an integer of 401 digits"
            closed = ws.receive()
            while closed["type"] != "websocket.close":
                closed = ws.receive()
            assert closed["code"] == 1008
        assert client.get("/status").json()["refused"]["closed"] == 1
    assert session.calls == []


def test_a_fault_of_the_consoles_own_is_a_refusal_and_a_strike_never_an_escape(monkeypatch, caplog):
    caplog.set_level(logging.WARNING)

    def broken(text, profiles):
        raise ZeroDivisionError("a bug of the console (test)")

    monkeypatch.setattr(console_server, "parse", broken)
    hub, session = ConsoleHub(), Session()
    with TestClient(create_app(hub, session), base_url=BASE) as client:
        with client.websocket_connect(WS) as ws:
            for _ in range(STRIKES):  # a command of the WebLab panel's: its parser reads it
                ws.send_text('{"cmd": "drive", "speed": 1, "turn": 0}')
                message = ws.receive()
                while message.get("text") is None or '"refused"' not in message["text"]:
                    message = ws.receive()
                assert "could not handle this message (ZeroDivisionError)" in message["text"]
            closed = ws.receive()
            while closed["type"] != "websocket.close":
                closed = ws.receive()
            assert closed["code"] == 1008
        assert client.get("/status").json()["refused"]["fault"] == STRIKES
    assert not [r for r in caplog.records if r.exc_info] and "Traceback" not in caplog.text
    said = [r.getMessage() for r in caplog.records if "handling it raised" in r.getMessage()]
    assert len(said) == STRIKES.bit_length()  # 1st, 2nd, 4th, 8th, 16th
    assert all("from testclient:" in s or "from testclient" in s for s in said), said


class _Recorder(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)


def test_over_uvicorn_a_hostile_message_keeps_the_connection_and_logs_no_traceback():
    recorder = _Recorder()
    watched = [logging.getLogger(n) for n in ("uvicorn", "uvicorn.error", "weblab.console")]
    for logger in watched:
        logger.addHandler(recorder)
    hub, session = ConsoleHub(), Session()
    try:
        with serving(hub, session) as url:
            ws_url = url.replace("http://", "ws://") + "/ws"
            with websockets_sync.connect(ws_url, subprotocols=HOLDER, open_timeout=10) as ws:
                deadline = time.monotonic() + 60
                hostile = [text for what, text in corpus() if not what.startswith("ping.extra")]
                for text in hostile[::7][: STRIKES - 2]:
                    ws.send(text)
                    ws.send('{"cmd": "ping"}')
                    while True:
                        reply = json.loads(ws.recv(timeout=max(0.1, deadline - time.monotonic())))
                        items = reply if isinstance(reply, list) else [reply]
                        if any(i["type"] == "pong" for i in items):
                            break
                ws.send('{"cmd": "drive", "speed": ' + HUGE + ', "turn": 0}')
                ws.send('{"cmd": "ping"}')
                seen = []
                while not any(i.get("type") == "pong" for i in seen):
                    reply = json.loads(ws.recv(timeout=10))
                    seen += reply if isinstance(reply, list) else [reply]
                assert any(
                    i["type"] == "refused" and "'speed' must be from 0 to 500" in i["why"]
                    for i in seen
                ), seen
    finally:
        for logger in watched:
            logger.removeHandler(recorder)
    assert not [r for r in recorder.records if r.exc_info or r.levelno >= logging.ERROR], [
        r.getMessage() for r in recorder.records
    ]


def test_requests_uvicorn_cannot_read_are_counted_not_logged_each_time(capfd):
    import socket
    import urllib.request

    hub, session = ConsoleHub(), Session()
    with serving(hub, session) as url:
        host, port = url.removeprefix("http://").rsplit(":", 1)
        for _ in range(200):
            with socket.create_connection((host, int(port)), timeout=5) as sock:
                sock.sendall(b"\x00\x01 not HTTP\r\n\r\n")
                sock.recv(1024)  # uvicorn's 400
        with urllib.request.urlopen(f"{url}/status", timeout=10) as response:
            refused = json.loads(response.read())["refused"]
    assert refused["invalid"] == 200, refused
    err = capfd.readouterr().err
    assert "WARNING:  Invalid HTTP request received." not in err  # uvicorn's own line
    assert len(err) < 5_000, err[-2000:]
