"""Debian's chromium, headless, driven by selenium through Debian's chromedriver (never a
downloaded browser build). Skips outside CI when either is missing; fails with CI=true."""

from __future__ import annotations

import os
import shutil

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


def chromium_driver():
    """A headless chromium WebDriver, window 1400 x 900; quit it when done."""
    webdriver = pytest.importorskip("selenium.webdriver")
    chromium, driver = browser_binaries()
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        f"--window-size={WINDOW[0]},{WINDOW[1]}",
    ):
        options.add_argument(arg)
    service = webdriver.ChromeService(executable_path=driver)
    return webdriver.Chrome(options=options, service=service)
