"""The console against other sites and other names (issue 22, items 3 and 11): a WebSocket from
another origin (cross-site WebSocket hijacking) and any request sent to a name the console does not
answer to (DNS rebinding) are refused; responses carry a Content-Security-Policy, X-Frame-Options
and Referrer-Policy; connections without the token have their own small cap and never take the
token holder's place; the token is presented when the WebSocket opens, never in a URL; a
non-loopback --host is warned about, naming the risk."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading

import pytest
from starlette.testclient import TestClient
from starlette.websockets import WebSocketDisconnect
from weblab_console.server import create_app
from weblab_console.serving import free_port

from acordcs.console.fanout import ConsoleHub
from acordcs.console.site_guard import allowed_names, host_name, same_origin
from tests.samples.weblab_console.conftest import WEBLAB_DIR
from tests.samples.weblab_console.test_console_server_holds_under_bad_viewers import (
    BASE,
    HOLDER,
    WS,
    Session,
    receive_until,
)


@pytest.fixture
def console():
    hub, session = ConsoleHub(max_viewers=2, max_watchers=3), Session()
    with TestClient(create_app(hub, session), base_url=BASE) as client:
        yield client, hub, session


@pytest.mark.parametrize(
    "origin",
    ["http://evil.example", "http://127.0.0.1:9999", "null", "http://127.0.0.1:8765.evil.example"],
)
def test_a_websocket_from_another_origin_is_refused_before_it_opens(console, origin):
    client, hub, _ = console
    with (
        pytest.raises(WebSocketDisconnect) as closed,
        client.websocket_connect(WS, headers={"origin": origin}),
    ):
        pass
    assert closed.value.code == 1008 and hub.viewers == 0


@pytest.mark.parametrize("origin", [None, "http://127.0.0.1:8765", "https://127.0.0.1:8765"])
def test_the_consoles_own_origin_and_clients_without_one_are_let_in(console, origin):
    client, _, _ = console
    headers = {"origin": origin} if origin else {}
    with client.websocket_connect(WS, headers=headers) as ws:
        assert receive_until(ws, "hello")["panel_state"]["weblab"]["profiles"]


@pytest.mark.parametrize(
    ("url", "origin"),
    [
        ("ws://localhost:8765/ws", "http://LOCALHOST:8765"),
        ("ws://localhost:8765/ws", "HTTP://LocalHost:8765"),
        ("ws://LOCALHOST:8765/ws", "http://localhost:8765"),
        ("ws://127.0.0.1:8765/ws", "HTTPS://127.0.0.1:8765"),
    ],
)
def test_the_origins_scheme_and_host_compare_case_insensitively(console, url, origin):
    # RFC 3986: scheme and host are case-insensitive; a client may send either case
    client, _, _ = console
    with client.websocket_connect(url, headers={"origin": origin}) as ws:
        assert receive_until(ws, "hello")["panel_state"]["weblab"]["profiles"]


@pytest.mark.parametrize(
    "origin",
    [
        "http://localhost:08765",  # the port compares exactly
        "http://localhost:8765/",
        "http://localhost",
        "http://user@localhost:8765",
        "ws://localhost:8765",
        "http://LOCALHOST.:8765",
        "http://localhost:8765 ",
    ],
)
def test_the_rest_of_the_origin_compares_exactly(console, origin):
    client, hub, _ = console
    with (
        pytest.raises(WebSocketDisconnect) as closed,
        client.websocket_connect("ws://localhost:8765/ws", headers={"origin": origin}),
    ):
        pass
    assert closed.value.code == 1008 and hub.viewers == 0


def test_same_origin_folds_the_case_of_scheme_and_host_only():
    assert same_origin("http://LOCALHOST:8765", "localhost:8765")
    assert same_origin("https://[::1]:8765", "[::1]:8765")
    assert same_origin("http://[FE80::1]:80", "[fe80::1]:80")
    assert not same_origin("http://[::1]:8766", "[::1]:8765")
    assert not same_origin("null", "localhost:8765")
    assert not same_origin("localhost:8765", "localhost:8765")
    assert not same_origin("http://localhost:8765", "localhost")


def test_refusals_are_counted_in_the_status_and_logged_with_the_peer(console, caplog):
    client, _, _ = console
    for _ in range(5):
        assert client.get("/", headers={"host": "evil.example"}).status_code == 400
    for _ in range(3):
        with (
            pytest.raises(WebSocketDisconnect),
            client.websocket_connect(WS, headers={"origin": "http://evil.example"}),
        ):
            pass
    refused = client.get("/status").json()["refused"]
    assert (refused["host"], refused["origin"]) == (5, 3)
    said = [r.getMessage() for r in caplog.records if "acordcs console: refused" in r.getMessage()]
    # the 1st, 2nd and 4th of the 5 requests, the 1st and 2nd of the 3 WebSockets
    assert len(said) == 5, said
    assert all("from testclient:50000" in s for s in said), said
    assert "Host 'evil.example'" in said[0] and "--allow-host NAME" in said[0]
    assert "Origin 'http://evil.example'" in said[-1] and "(2 refused so far" in said[-1]


@pytest.mark.parametrize("path", ["/", "/static/console.js", "/status"])
def test_a_request_sent_to_another_name_is_refused_with_the_reason(console, path):
    client, _, _ = console
    refused = client.get(path, headers={"host": "evil.example:8765"})
    assert refused.status_code == 400
    assert "Host 'evil.example:8765' is not a name this console answers to" in refused.text
    assert "--allow-host" in refused.text
    assert refused.headers["x-frame-options"] == "DENY"


def test_a_websocket_sent_to_another_name_is_refused(console):
    client, hub, _ = console
    # a rebound name: the page's own origin matches its Host, but the Host is not the console's
    with (
        pytest.raises(WebSocketDisconnect),
        client.websocket_connect(
            "ws://evil.example:8765/ws", headers={"origin": "http://evil.example:8765"}
        ),
    ):
        pass
    assert hub.viewers == 0


@pytest.mark.parametrize("path", ["/", "/static/console.js", "/static/console.css", "/status"])
def test_every_response_carries_the_security_headers(console, path):
    client, _, _ = console
    response = client.get(path)
    assert response.status_code == 200
    policy = response.headers["content-security-policy"]
    assert "script-src 'self';" in policy and "style-src 'self';" in policy
    assert "unsafe-inline" not in policy and "unsafe-eval" not in policy
    assert "frame-ancestors 'none'" in policy and "default-src 'none'" in policy
    assert "connect-src 'self' ws://127.0.0.1:8765 wss://127.0.0.1:8765" in policy
    assert response.headers["x-frame-options"] == "DENY"
    assert response.headers["referrer-policy"] == "no-referrer"
    assert response.headers["x-content-type-options"] == "nosniff"


def test_idle_connections_without_the_token_never_lock_out_the_token_holder(console):
    client, hub, session = console
    watchers = [client.websocket_connect(WS) for _ in range(hub.max_watchers)]
    try:
        for ws in (c.__enter__() for c in watchers):
            receive_until(ws, "hello")
        with client.websocket_connect(WS) as extra:  # one more without the token: turned away
            refused = json.loads(extra.receive()["text"])
            assert "maximum of 3 viewers without the token" in refused["why"]
            assert extra.receive()["code"] == 1013
        with client.websocket_connect(WS, subprotocols=HOLDER) as holder:
            assert holder.accepted_subprotocol == "acordcs"
            receive_until(holder, "authorized")
            holder.send_text(json.dumps({"cmd": "stop"}))
            assert receive_until(holder, "done")["cmd"] == "stop"
    finally:
        for c in watchers:
            c.__exit__(None, None, None)
    assert session.calls == [("stop",)]


def test_a_wrong_token_at_the_handshake_watches_only_and_is_told(console):
    client, hub, session = console
    with client.websocket_connect(WS, subprotocols=["acordcs", "acordcs.token.guess"]) as ws:
        assert "does not know this token" in receive_until(ws, "refused")["why"]
        ws.send_text(json.dumps({"cmd": "stop"}))
        assert "needs the session's token" in receive_until(ws, "refused")["why"]
        assert hub.stats()["watchers"] == 1
    assert session.calls == []


def test_the_page_takes_its_token_from_the_fragment_and_never_from_a_url(console):
    client, _, _ = console
    script = client.get("/static/console.js").text
    assert "location.hash" in script and "history.replaceState" in script
    assert "sessionStorage" in script and "location.search).get" not in script


def test_the_names_a_console_answers_to():
    assert allowed_names("127.0.0.1") == {"127.0.0.1", "localhost", "::1"}
    assert allowed_names("192.168.1.5") == {"192.168.1.5"}
    assert allowed_names("0.0.0.0", ["lab.example:8765"]) == {
        "lab.example",
        "127.0.0.1",
        "localhost",
        "::1",
    }
    assert host_name("[::1]:8765") == "::1" and host_name("LocalHost:80") == "localhost"


def run_console(*args: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "weblab_console", *args],
        cwd=WEBLAB_DIR,
        env={
            **os.environ,
            "PYTHONPATH": WEBLAB_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""),
        },
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def first_line(stream, timeout: float = 60.0) -> str:
    got: list[str] = []
    reader = threading.Thread(target=lambda: got.append(stream.readline()), daemon=True)
    reader.start()
    reader.join(timeout)
    return got[0] if got else ""


def test_a_non_loopback_host_is_warned_about_and_its_link_names_the_allowed_host(weblab_app):
    port = free_port()
    console = run_console("--host", "0.0.0.0", "--allow-host", "lab.example", "--port", str(port))
    try:
        line = first_line(console.stdout)  # the URL: the console is up
        assert line.startswith(f"WebLab console: http://lab.example:{port}/#token="), line
        assert "?token" not in line
    finally:
        console.send_signal(signal.SIGINT)
        _, err = console.communicate(timeout=60)
    assert "warning: --host 0.0.0.0 is not a loopback address" in err
    assert "clear text" in err and "SSH tunnel" in err
    assert console.returncode == 0


def test_a_wildcard_host_without_a_name_is_a_usage_error():
    console = run_console("--host", "0.0.0.0")
    _, err = console.communicate(timeout=60)
    assert console.returncode == 2
    assert "name the one browsers will use with --allow-host NAME" in err


def test_a_loopback_console_says_nothing_about_exposure(weblab_app):
    console = run_console("--port", str(free_port()))
    try:
        line = first_line(console.stdout)
        assert line.startswith("WebLab console: http://127.0.0.1:") and "/#token=" in line
    finally:
        console.send_signal(signal.SIGINT)
        _, err = console.communicate(timeout=60)
    assert "warning" not in err and console.returncode == 0
