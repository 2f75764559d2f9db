"""``python -m weblab_console.screenshot OUT.png [--profile residential] [--seed 0] [--at 90]``:
a screenshot of the console (1400 x 900) during a run, taken by Debian's chromium (headless,
driven by selenium through chromedriver) once the run reaches ``--at`` simulated seconds. The
run is sped up (``--speed``) so that this takes seconds; the console looks the same.

``--attach APP``: the console attached to the application built in APP and started by its scripts
(for instance ``WEBLAB_LIVE_SECONDS=60 sh live.sh`` in another terminal, which prints where its
processes serve; the same environment here), once its WebLab process's clock reaches ``--at``
seconds."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from acordcs.console.attaching import Application
from acordcs.console.fanout import ConsoleHub
from acordcs.console.live_session import LiveSession
from weblab_console.attached import HOW_TO_START, TIMEOUT
from weblab_console.server import live_console
from weblab_console.serving import serving
from weblab_console.session import ConsoleSession

TOKEN = "screenshot"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m weblab_console.screenshot")
    parser.add_argument("out", type=Path)
    parser.add_argument("--profile", default="residential")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--at", type=float, default=90.0, help="simulated seconds into the run")
    parser.add_argument("--speed", type=float, default=8.0)
    parser.add_argument("--chromium", default="/usr/bin/chromium")
    parser.add_argument("--chromedriver", default="/usr/bin/chromedriver")
    parser.add_argument("--attach", metavar="APP", type=Path)
    args = parser.parse_args(argv)
    from selenium import webdriver
    from selenium.webdriver.support.ui import Select, WebDriverWait

    options = webdriver.ChromeOptions()
    options.binary_location = args.chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,1300"):
        options.add_argument(arg)
    hub = ConsoleHub()
    session: ConsoleSession | LiveSession
    if args.attach is not None:  # serving() attaches it
        session = live_console(hub, TOKEN, Application.built_in(args.attach, TIMEOUT, HOW_TO_START))
    else:
        session = ConsoleSession(hub, TOKEN, speed=args.speed)
    browser = webdriver.Chrome(options=options, service=webdriver.ChromeService(args.chromedriver))
    try:
        # The page's viewport is 1400 x 1300 (the window would be that size with its frame).
        browser.execute_cdp_cmd(
            "Emulation.setDeviceMetricsOverride",
            {"width": 1400, "height": 1300, "deviceScaleFactor": 1, "mobile": False},
        )
        with serving(hub, session) as url:
            browser.get(f"{url}/#token={TOKEN}")
            wait = WebDriverWait(browser, 60 + args.at, poll_frequency=0.1)
            wait.until(lambda d: d.find_elements("css selector", "#profile option"))
            if isinstance(session, ConsoleSession):
                Select(browser.find_element("id", "profile")).select_by_value(args.profile)
                seed = browser.find_element("id", "seed")
                seed.clear()
                seed.send_keys(str(args.seed))
                browser.find_element("id", "start").click()
            wait.until(
                lambda d: float(d.find_element("id", "map").get_attribute("data-t") or 0) >= args.at
            )
            if isinstance(session, ConsoleSession):
                session.set_speed(1.0)  # hold still while the picture is taken
            time.sleep(1.0)
            args.out.parent.mkdir(parents=True, exist_ok=True)
            browser.get_screenshot_as_file(str(args.out))
    finally:
        browser.quit()
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
