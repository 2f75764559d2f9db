"""Debian's chromium, headless, driven by selenium through Debian's chromedriver (never a
downloaded browser build). Skips outside CI when either is missing; fails with CI=true."""

from __future__ import annotations

import contextlib
import os
import shutil
from collections.abc import Iterator

import pytest

CHROMIUM_CANDIDATES = ("/usr/bin/chromium", shutil.which("chromium"))
DRIVER_CANDIDATES = ("/usr/bin/chromedriver", shutil.which("chromedriver"))
WINDOW = (1400, 900)


def _found(candidates: tuple[str | None, ...]) -> str | None:
    return next((c for c in candidates if c and os.access(c, os.X_OK)), None)


def browser_binaries() -> tuple[str, str]:
    """(chromium, chromedriver); skip without them, except in CI where they must be there."""
    chromium, driver = _found(CHROMIUM_CANDIDATES), _found(DRIVER_CANDIDATES)
    if chromium and driver:
        return chromium, driver
    missing = [n for n, p in (("chromium", chromium), ("chromedriver", driver)) if not p]
    message = (
        f"{' and '.join(missing)} not found (install the Debian packages 'chromium' and "
        "'chromium-driver': /usr/bin/chromium, /usr/bin/chromedriver)"
    )
    if os.environ.get("CI") == "true":
        pytest.fail(message + "; browser tests must run in CI")
    pytest.skip(message)


def chromium_driver(width: int = WINDOW[0], height: int = WINDOW[1]):
    """A headless chromium WebDriver, window ``width`` x ``height``; quit it when done."""
    webdriver = pytest.importorskip("selenium.webdriver")
    chromium, driver = browser_binaries()
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    # the page's console messages (CSP refusals among them), for get_log("browser")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        f"--window-size={width},{height}",
    ):
        options.add_argument(arg)
    service = webdriver.ChromeService(executable_path=driver)
    return webdriver.Chrome(options=options, service=service)


@contextlib.contextmanager
def headless_chromium(width: int = WINDOW[0], height: int = WINDOW[1]) -> Iterator[object]:
    """:func:`chromium_driver` for a ``with`` block, quit at its end."""
    driver = chromium_driver(width, height)
    try:
        yield driver
    finally:
        driver.quit()
