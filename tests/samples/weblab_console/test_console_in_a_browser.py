"""The console in a real headless browser (Debian's chromium through chromedriver) over the real
experiment, sped up five times: the page loads and authorizes with the URL's token; before the
first frame each camera panel shows a placeholder, not a broken image; both camera panels update;
the map draws the trajectory; the context panel shows values and a policy panel a firing with its
rules' degrees; the plots have a time axis; manual control moves the robot and handing back works;
a viewer without the token is refused with the reason shown; a run started elsewhere shows its
network and seed in the form; the page says so when the server goes away."""

from __future__ import annotations

import pytest
from weblab_console.serving import serving
from weblab_console.session import ConsoleSession

from acordcs.console.fanout import ConsoleHub
from tests.support.browser import chromium_driver

TOKEN = "browser-test-token"
SPEED = 5.0
WAIT = 15.0


@pytest.fixture(scope="module")
def console(weblab_app):
    hub = ConsoleHub(max_viewers=8)
    session = ConsoleSession(hub, TOKEN, speed=SPEED)
    with serving(hub, session) as url:
        yield url, session


@pytest.fixture(scope="module")
def browser():
    driver = chromium_driver()
    try:
        yield driver
    finally:
        driver.quit()


def until(browser, condition, what: str, timeout: float = WAIT):
    from selenium.webdriver.support.ui import WebDriverWait

    return WebDriverWait(browser, timeout, poll_frequency=0.1).until(
        lambda d: condition(d), message=f"the page never showed {what}"
    )


def attr(browser, element_id: str, name: str) -> str:
    return browser.find_element("id", element_id).get_attribute(name) or ""


def text(browser, element_id: str) -> str:
    return browser.find_element("id", element_id).text


def set_range(browser, element_id: str, value: int) -> None:
    browser.execute_script(
        "const el = document.getElementById(arguments[0]); el.value = arguments[1];"
        "el.dispatchEvent(new Event('input'));",
        element_id,
        value,
    )


def test_the_page_shows_a_running_experiment_in_every_panel(console, browser):
    from selenium.webdriver.support.ui import Select

    url, _session = console
    browser.get(f"{url}/#token={TOKEN}")
    until(browser, lambda d: "the hands are yours" in text(d, "message"), "the token accepted")
    # the token left the address bar and the history entry: the link's fragment is gone
    assert browser.current_url == f"{url}/"
    entries = browser.execute_cdp_cmd("Page.getNavigationHistory", {})["entries"]
    assert entries[-1]["url"] == f"{url}/" and not any("token" in e["url"] for e in entries)
    # No run yet: each camera panel says so, no image (a broken-image icon) is shown.
    for camera in ("onboard", "panoramic"):
        assert not browser.find_element("id", camera).is_displayed()
        assert "no frame yet" in text(browser, f"{camera}-waiting")
    Select(browser.find_element("id", "profile")).select_by_value("residential")
    browser.find_element("id", "seed").clear()
    browser.find_element("id", "seed").send_keys("3")
    browser.find_element("id", "start").click()
    until(browser, lambda d: "residential, seed 3" in text(d, "profile-shown"), "the run started")

    # Both cameras update: frames counted, and the picture's URL changes.
    for camera in ("onboard", "panoramic"):
        until(
            browser,
            lambda d, c=camera: int(attr(d, c, "data-frames") or 0) >= 2,
            f"{camera} frames",
        )
        first = attr(browser, camera, "src")
        until(browser, lambda d, c=camera, f=first: attr(d, c, "src") != f, f"a new {camera} frame")
        assert attr(browser, camera, "src").startswith("blob:")
        assert browser.find_element("id", camera).is_displayed()
        assert not browser.find_element("id", f"{camera}-waiting").is_displayed()

    # The map draws a trajectory that grows.
    until(browser, lambda d: int(attr(d, "map", "data-points") or 0) >= 3, "a trajectory")

    # Around the panel, the console's page over the experiment's containers: the diagram,
    # the monitors' plots gaining points, a fuzzy set's firing writing the speed limit.
    names = browser.execute_script(
        "return [...document.querySelectorAll('#architecture g.element')]"
        ".map((g) => g.dataset.name)"
    )
    assert {"UserSide", "WebLabSide", "Navigator", "Telemetry", "SpeedLimiting"} <= set(names)
    plot = 'figure[data-series="Telemetry.batteryVoltage"]'
    points = lambda d: int(d.find_element("css selector", plot).get_attribute("data-points") or 0)  # noqa: E731
    until(browser, lambda d: points(d) >= 1, "a first point of Telemetry.batteryVoltage")
    first = points(browser)
    until(browser, lambda d: points(d) > first, "the battery's plot gaining a point")
    firing = '.policy-set[data-set="SpeedLimiting"]'
    until(
        browser,
        lambda d: "Locomotion.maxSpeed" in d.find_element("css selector", firing).text,
        "SpeedLimiting's firing, writing Locomotion.maxSpeed",
    )
    until(browser, lambda d: "SpeedLimiting" in text(d, "firings"), "the log of firings")


def test_the_content_security_policy_refuses_nothing_the_page_does(console, browser):
    # after the page ran every panel (the test above): no CSP refusal in its console
    refusals = [
        entry["message"]
        for entry in browser.get_log("browser")
        if "Content Security Policy" in entry["message"] or "Refused to" in entry["message"]
    ]
    assert refusals == []
    policy = browser.execute_script(
        "return fetch('/').then((r) => r.headers.get('content-security-policy'))"
    )
    assert "script-src 'self'" in policy and "unsafe-inline" not in policy


def test_manual_control_moves_the_robot_and_hands_back(console, browser):
    _url, session = console
    assert session.running, "the previous test started a run in this page"
    set_range(browser, "speed", 150)
    set_range(browser, "turn", 20)
    browser.find_element("id", "take").click()
    until(browser, lambda d: attr(d, "map", "data-driver") == "manual", "manual control")
    assert "You drive" in text(browser, "driver")
    pose = attr(browser, "map", "data-pose")
    until(
        browser,
        lambda d: attr(d, "map", "data-pose") != pose and attr(d, "map", "data-driver") == "manual",
        "the robot moving under manual control",
    )
    until(browser, lambda d: "manual control taken" in text(d, "events"), "the event")

    browser.find_element("id", "release").click()
    until(browser, lambda d: attr(d, "map", "data-driver") == "navigator", "the Navigator back")
    assert "Navigator drives" in text(browser, "driver")
    until(browser, lambda d: "handed back" in text(d, "events"), "the hand-back event")


def test_a_viewer_without_the_token_is_refused_with_the_reason_shown(console, browser):
    url, session = console
    browser.execute_script("sessionStorage.clear()")  # as a new tab, which has none
    browser.get(f"{url}/")
    until(browser, lambda d: "watching only" in text(d, "message"), "the watching-only notice")
    until(browser, lambda d: d.find_elements("css selector", "#profile option"), "the profiles")
    browser.find_element("id", "stop").click()
    until(browser, lambda d: "needs the session's token" in text(d, "message"), "the refusal")
    assert "refused" in attr(browser, "message", "class")
    assert session.running, "the refused stop did not reach the experiment"
    # A wrong token is refused by the access service.
    browser.get(f"{url}/#token=not-the-token")
    until(
        browser,
        lambda d: "does not know this token" in text(d, "message"),
        "the wrong token refused",
    )


def test_a_run_started_elsewhere_shows_its_network_and_seed_in_the_form(weblab_app, browser):
    # As `python -m weblab_console --start campus --seed 7` does: the run starts before any page.
    hub = ConsoleHub()
    session = ConsoleSession(hub, TOKEN, speed=SPEED)
    with serving(hub, session) as url:
        session.start("campus", 7)
        browser.get(f"{url}/#token={TOKEN}")
        until(browser, lambda d: "campus, seed 7" in text(d, "profile-shown"), "the run")
        until(browser, lambda d: attr(d, "seed", "value") == "7", "the seed in the form")
        assert attr(browser, "profile", "value") == "campus"
        # A seed typed for the next run stays as typed while the same run goes on.
        browser.find_element("id", "seed").clear()
        browser.find_element("id", "seed").send_keys("12")
        t = float(attr(browser, "map", "data-t"))
        until(browser, lambda d: float(attr(d, "map", "data-t")) > t + 1, "the run going on")
        assert attr(browser, "seed", "value") == "12"


def test_the_page_says_disconnected_when_the_console_goes_away(weblab_app, browser):
    hub = ConsoleHub()
    session = ConsoleSession(hub, TOKEN, speed=SPEED)
    with serving(hub, session) as url:
        browser.get(f"{url}/#token={TOKEN}")
        until(browser, lambda d: text(d, "connection") == "live", "live")
        browser.find_element("id", "start").click()
        until(browser, lambda d: attr(d, "map", "data-running") == "true", "the run")
    # The server and its experiment are gone: the page tells, it does not hang or show stale data as live.
    until(browser, lambda d: text(d, "connection") == "disconnected", "disconnected")
    assert "off" in attr(browser, "connection", "class")
