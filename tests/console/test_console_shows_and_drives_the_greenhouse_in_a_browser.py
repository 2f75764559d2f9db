"""``acordcs-gen console`` on the tutorial's greenhouse, started by its generated scripts, in
Debian's headless chromium (issue 31): the diagram shows every container, component, monitor and
policy set of the descriptor, each clickable with its qualified name and model id; the monitor's
plot gains points; a firing of the fuzzy set appears with each rule's degree, which is the
membership of the input shown in the rule's term (computed here from the model's parameters: an
oracle independent of the engine); a property set from the form reaches the container (read back
through its management interface); an update planned from the page shows the plan, and once
applied the next firing follows the changed rule. A cross-site page, a wrong Host and a viewer
without the token are refused. The generated ``bin/console`` serves the page and stops on TERM."""

from __future__ import annotations

import http.client
import json
import re
import threading
import urllib.request
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import urlsplit

import pytest

from tests.console.attached_console import TOKEN, attached
from tests.support.toolchain import SAMPLES

pytestmark = pytest.mark.service

WAIT = 20.0
GREENHOUSE = SAMPLES / "tutorial" / "greenhouse.uml"


@pytest.fixture(scope="module")
def greenhouse(tmp_path_factory):
    with attached(GREENHOUSE, "greenhouse_app", tmp_path_factory.mktemp("greenhouse")) as found:
        yield found


@pytest.fixture(scope="module")
def browser(greenhouse, chromium):
    chromium.get(f"{greenhouse.url}/#token={TOKEN}")
    return chromium


def until(browser, condition, what: str, timeout: float = WAIT):
    from selenium.webdriver.support.ui import WebDriverWait

    return WebDriverWait(browser, timeout, poll_frequency=0.1).until(
        lambda d: condition(d), message=f"the page never showed {what}"
    )


def read(browser, selector: str) -> str | None:
    """The text of ``selector``'s element, read at once in the page (the page replaces a
    firing's table at each firing: a reference held across two calls may be gone)."""
    return browser.execute_script(
        "const e = document.querySelector(arguments[0]); return e ? e.textContent : null;", selector
    )


def names(browser, kind: str) -> set[str]:
    found = browser.find_elements("css selector", f'g.element[data-kind="{kind}"]')
    return {e.get_attribute("data-name") for e in found}


def test_the_diagram_shows_every_element_of_the_descriptor_each_with_its_name_and_id(
    greenhouse, browser
):
    app = greenhouse.descriptor
    until(browser, lambda d: names(d, "container"), "the diagram")
    assert names(browser, "container") == {c.name for c in app.containers}
    assert names(browser, "component") == {c.name for c in app.components} == {"Sensor", "Vent"}
    assert names(browser, "monitor") == {m.name for m in app.monitors}
    assert names(browser, "policy-set") == {s.name for s in app.policy_sets}
    vent = next(c for c in app.components if c.name == "Vent")
    browser.find_element("css selector", 'g.element[data-name="Vent"] rect').click()
    shown = lambda field: browser.find_element("css selector", f'#details dd[data-field="{field}"]')  # noqa: E731
    until(browser, lambda d: shown("model id").text == vent.id, "Vent's model id")
    assert shown("qualified name").text == vent.qualified_name
    assert shown("kind").text == "component"
    refused = [
        e["message"] for e in browser.get_log("browser") if "Content Security" in e["message"]
    ]
    assert not refused  # the page runs whole under its own CSP


def test_the_monitors_plot_gains_points(browser):
    plot = 'figure[data-series="Climate.temperature"]'
    points = lambda d: int(d.find_element("css selector", plot).get_attribute("data-points") or 0)  # noqa: E731
    until(browser, lambda d: points(d) >= 1, "a first point of Climate.temperature")
    first = points(browser)
    until(browser, lambda d: points(d) > first, "Climate.temperature's plot gaining a point")
    caption = browser.find_element("css selector", f"{plot} figcaption").text
    assert "0 to 50" in caption  # the range of the Ventilation set's variable, from the model


def membership(shape: str, parameters: tuple[float, ...], x: float) -> float:
    """A term's membership at ``x``: the exact formula of its shape (the oracle)."""
    if shape == "triangle":
        a, b, c = parameters
        parameters = (a, b, b, c)
    a, b, c, d = parameters
    if x < a or x > d:
        return 0.0
    if b <= x <= c:
        return 1.0
    return (x - a) / (b - a) if x < b else (d - x) / (d - c)


def test_a_firing_appears_with_each_rules_degree_the_membership_of_its_input(greenhouse, browser):
    table = '.policy-set[data-set="Ventilation"] table'
    until(browser, lambda d: read(d, table) is not None, "a firing of Ventilation")
    rows = dict(
        browser.execute_script(
            "return [...document.querySelectorAll(arguments[0])].map("
            "r => [r.querySelector('th').textContent, r.querySelector('td').textContent]);",
            f"{table} tr",
        )
    )
    temperature = float(rows["in Climate.temperature"])
    variable = next(
        v for v in greenhouse.descriptor.policy_sets[0].variables if v.attribute == "temperature"
    )
    rules = greenhouse.descriptor.policy_sets[0].rules()
    for rule in rules:  # "if temperature is <term> then ..."
        term = next(t for t in variable.terms if re.search(rf"\bis {t.name}\b", rule.text))
        expected = membership(term.shape, term.parameters, temperature)
        assert float(rows[f"VentRules.{rule.label}"]) == pytest.approx(expected, abs=0.006)
    until(browser, lambda d: "Ventilation:" in d.find_element("id", "firings").text, "the log")


def test_a_property_set_from_the_page_reaches_the_container(greenhouse, browser):
    from selenium.webdriver.support.ui import Select

    Select(browser.find_element("id", "property")).select_by_visible_text(
        "Vent.opening: double (default 0)"
    )
    field = browser.find_element("id", "property-value")
    field.clear()
    field.send_keys("12.5")
    browser.find_element("id", "set").click()
    until(browser, lambda d: "→ 12.5" in d.find_element("id", "set-result").text, "the change")
    # The container says what it holds now, unless a firing rewrote it meanwhile: either the
    # value set or the set's own output (its last firing's), never anything else.
    now = greenhouse.session.app.manage("House", "properties", ["Vent"])["Vent"]["opening"]
    fired = greenhouse.session.app.manage("House", "status")["policy_sets"]["Ventilation"]
    assert now in (12.5, fired["outputs"]["Vent.opening"])


def test_an_update_from_the_page_is_planned_then_applied_and_the_next_firing_follows_it(
    greenhouse, browser
):
    text = greenhouse.model.read_text(encoding="utf-8")
    changed = text.replace("then Vent.opening is wide", "then Vent.opening is half")
    assert changed != text
    greenhouse.model.write_text(changed, encoding="utf-8")
    browser.find_element("id", "plan").click()
    plan = lambda d: d.find_element("id", "plan-text").text  # noqa: E731
    until(browser, lambda d: "(exit 0)" in plan(d), "the plan", timeout=60)
    assert "dry run: nothing changed" in plan(browser) and "hot" in plan(browser), plan(browser)
    browser.find_element("id", "apply").click()
    until(browser, lambda d: "applying" not in plan(d) and "(exit" in plan(d), "the update", 60)
    assert "(exit 0)" in plan(browser), plan(browser)
    events = lambda d: d.find_element("id", "events").text  # noqa: E731
    until(browser, lambda d: "model.updated" in events(d), "model.updated in the events")
    # Hot (45 degrees, the sensor's cap) now opens the vent half: the centroid of "half".
    output = '.policy-set[data-set="Ventilation"] tr.output td'
    until(
        browser,
        lambda d: read(d, output) == "50",
        "a firing following the changed rule (Vent.opening 50)",
    )


def test_a_model_sent_from_the_page_is_planned_with_its_errors_and_then_applied(
    greenhouse, browser
):
    # After the test above the running rule says "half": the tutorial's own text says "wide".
    text = (SAMPLES / "tutorial" / "greenhouse.acord").read_text(encoding="utf-8")
    plan = lambda d: d.find_element("id", "plan-text").text  # noqa: E731
    browser.execute_script("document.getElementById('model-upload').open = true")

    def send(name: str, body: str) -> None:
        browser.execute_script(
            "document.getElementById('model-name').value = arguments[0];"
            "document.getElementById('model-text').value = arguments[1];",
            name,
            body,
        )
        browser.find_element("id", "plan-upload").click()

    broken = text.replace("hot: if temperature is hot", "hot: if temperature is", 1)
    send("greenhouse.acord", broken)
    until(browser, lambda d: "(exit" in plan(d) or "refused" in plan(d), "the model's plan", 60)
    assert "(exit 1)" in plan(browser), plan(browser)  # the model has errors: nothing built
    assert re.search(r"^greenhouse\.acord:\d+:\d+: ", plan(browser), re.M), plan(browser)
    assert not browser.find_element("id", "apply").is_enabled()
    send("greenhouse.acord", text)
    until(browser, lambda d: "(exit 0)" in plan(d), "the plan of the model sent", timeout=60)
    assert "dry run: nothing changed" in plan(browser) and "wide" in plan(browser), plan(browser)
    browser.find_element("id", "apply").click()
    until(browser, lambda d: "applying" not in plan(d) and "(exit" in plan(d), "the update", 60)
    assert "(exit 0)" in plan(browser), plan(browser)
    output = '.policy-set[data-set="Ventilation"] tr.output td'
    until(browser, lambda d: read(d, output) != "50", "a firing following the rule sent (wide)")


def test_a_model_without_the_token_or_too_large_is_refused_before_it_is_read(greenhouse):
    where = urlsplit(greenhouse.url)
    named = {"X-Acordcs-Model-Name": "m.acord", "Content-Type": "text/plain"}
    for headers, body, status in (
        (named, b"application X {}", 403),
        ({**named, "X-Acordcs-Token": "not-the-token"}, b"application X {}", 403),
        ({**named, "X-Acordcs-Token": TOKEN, "X-Acordcs-Model-Name": "../m.acord"}, b"", 400),
        ({**named, "X-Acordcs-Token": TOKEN}, b"x" * (2 * 1024 * 1024 + 1), 413),
        ({**named, "X-Acordcs-Token": TOKEN, "Origin": "http://evil.example"}, b"", 403),
    ):
        connection = http.client.HTTPConnection(where.hostname, where.port, timeout=10)
        connection.request("POST", "/model", body=body, headers=headers)
        reply = connection.getresponse()
        assert reply.status == status, (headers, reply.read()[:200])
        connection.close()


# ------------------------------------------------------------------------------------ refused
class _Foreign(BaseHTTPRequestHandler):
    """Another site's page, which tries to open the console's live stream."""

    target = ""

    def do_GET(self) -> None:
        page = (
            "<!doctype html><title>waiting</title><script>"
            f"const s = new WebSocket({self.target!r}, ['acordcs']);"
            "s.onopen = () => { document.title = 'opened'; };"
            "s.onclose = (e) => { if (document.title !== 'opened') document.title = 'closed'; };"
            "</script>"
        ).encode()
        self.send_response(200)
        self.send_header("content-type", "text/html")
        self.send_header("content-length", str(len(page)))
        self.end_headers()
        self.wfile.write(page)

    def log_message(self, *args) -> None:
        pass


def test_a_cross_site_page_cannot_open_the_live_stream(greenhouse, browser):
    before = greenhouse.refusals.counts().get("origin", 0)
    where = urlsplit(greenhouse.url)
    _Foreign.target = f"ws://{where.netloc}/ws"
    foreign = ThreadingHTTPServer(("127.0.0.1", 0), _Foreign)
    threading.Thread(target=foreign.serve_forever, daemon=True).start()
    try:
        browser.switch_to.new_window("tab")
        browser.get(f"http://127.0.0.1:{foreign.server_address[1]}/")
        until(browser, lambda d: d.title in ("opened", "closed"), "the foreign page's attempt")
        assert browser.title == "closed"
        assert greenhouse.refusals.counts()["origin"] == before + 1
    finally:
        foreign.shutdown()
        browser.close()
        browser.switch_to.window(browser.window_handles[0])


def test_a_request_sent_to_another_name_is_refused(greenhouse):
    where = urlsplit(greenhouse.url)
    connection = http.client.HTTPConnection(where.hostname, where.port, timeout=10)
    connection.request("GET", "/", headers={"Host": f"evil.example:{where.port}"})
    answer = connection.getresponse()
    assert answer.status == 400
    assert "is not a name this console answers to" in answer.read().decode()
    connection.close()


def test_a_viewer_without_the_token_sees_nothing_of_an_application_started_with_one(
    greenhouse, browser
):
    browser.switch_to.new_window("tab")  # a tab of its own: no token in its session storage
    try:
        browser.get(f"{greenhouse.url}/")
        until(browser, lambda d: d.find_element("id", "connection").text == "refused", "refusal")
        assert "only to viewers holding its token" in browser.find_element("id", "message").text
        assert not browser.find_elements("css selector", "g.element")
    finally:
        browser.close()
        browser.switch_to.window(browser.window_handles[0])


def test_the_generated_bin_console_serves_the_page_and_stops_on_term(greenhouse):
    import signal
    import subprocess

    from tests.generator.test_shell_scripts_parse_quote_and_run import free_ports

    port = free_ports(1)[0]
    child = subprocess.Popen(
        ["sh", str(greenhouse.out / "bin" / "console"), "--port", str(port)],
        env=greenhouse.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        attached_line = child.stdout.readline()
        link = child.stdout.readline()
        assert attached_line.startswith("acordcs console: attached to Greenhouse: House at "), (
            attached_line + child.stderr.read()
        )
        assert re.fullmatch(
            rf"acordcs console: http://127\.0\.0\.1:{port}/#token=[A-Za-z0-9_-]{{22}}\n", link
        ), link
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=10) as page:
            assert "acordcs console" in page.read().decode()
            assert "frame-ancestors 'none'" in page.headers["content-security-policy"]
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=10) as status:
            assert json.load(status)["mode"] == "attached"
        child.send_signal(signal.SIGTERM)
        out, err = child.communicate(timeout=20)
        assert child.returncode == 0, err
        assert "acordcs console stopped" in out
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()


def test_a_single_process_run_serves_the_same_console_beside_its_container(greenhouse):
    import os
    import signal
    import subprocess
    import sys

    websockets_sync = pytest.importorskip("websockets.sync.client")
    env = {k: v for k, v in greenhouse.env.items() if not k.startswith("ACORDCS_")}
    env["PYTHONPATH"] = os.pathsep.join([str(greenhouse.out), env.get("PYTHONPATH", "")])
    child = subprocess.Popen(
        [sys.executable, "-m", "greenhouse_app.House", "--clock", "real", "--console", "0",
         "--duration", "60"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        link = ""
        while "console:" not in link:
            link = child.stdout.readline()
            assert link, child.stderr.read()
        found = re.search(r"http://(127\.0\.0\.1:\d+)/#token=([A-Za-z0-9_-]+)", link)
        assert found, link
        where, token = found.groups()
        kinds: set[str] = set()
        with websockets_sync.connect(
            f"ws://{where}/ws", subprotocols=["acordcs", f"acordcs.token.{token}"]
        ) as ws:
            while not {"application", "fired"} <= kinds:
                message = json.loads(ws.recv(timeout=WAIT))
                for m in message if isinstance(message, list) else [message]:
                    kinds.add(m["type"])
                    if m["type"] == "event":
                        kinds.add(m["data"]["kind"])
                    if m["type"] == "application":
                        assert [c for c in m["data"]["containers"]] == ["House"]
        with urllib.request.urlopen(f"http://{where}/status", timeout=10) as status:
            assert json.load(status)["mode"] == "single process"
        child.send_signal(signal.SIGTERM)
        out, _ = child.communicate(timeout=20)
        assert "House: stopped at" in out and child.returncode == 0
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()


def test_a_hold_and_its_release_are_events(greenhouse, browser):
    app = greenhouse.session.app
    app.manage("House", "hold", "Sensor", 30.0)  # as a console driving holds a component
    events = lambda d: read(d, "#events") or ""  # noqa: E731
    until(browser, lambda d: "House: hold on Sensor" in events(d), "the hold in the events")
    app.manage("House", "release", "Sensor")
    until(browser, lambda d: "House: Sensor released" in events(d), "the release in the events")


def test_a_container_that_stops_answering_is_an_event(greenhouse, browser):
    # The module's last test: it stops the greenhouse (the fixture's stop-all finds it stopped).
    from tests.support.scripts import script

    stopped = script(greenhouse.out / "bin", "House-stop", greenhouse.env, timeout=60)
    assert stopped.returncode == 0, stopped.stdout + stopped.stderr
    until(
        browser,
        lambda d: "House stopped answering" in (read(d, "#events") or ""),
        "the container stopping in the events",
    )
