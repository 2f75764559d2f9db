"""A real browser for tests: Debian's chromium, headless, driven by selenium through Debian's
chromedriver of the same version (never a downloaded browser build). Skips when they are missing,
except in CI (``CI=true``), where ``make test`` installs them and a missing one fails the test."""

from __future__ import annotations

import contextlib
import os
import shutil
from collections.abc import Iterator

import pytest

CHROMIUM = ("/usr/bin/chromium", shutil.which("chromium"))
CHROMEDRIVER = ("/usr/bin/chromedriver", shutil.which("chromedriver"))


def _found(candidates: tuple[str | None, ...]) -> str | None:
    return next((c for c in candidates if c and os.access(c, os.X_OK)), None)


def chromium_paths() -> tuple[str, str]:
    """(chromium, chromedriver); skip without them, except in CI where they must be there."""
    browser, driver = _found(CHROMIUM), _found(CHROMEDRIVER)
    if browser and driver:
        return browser, driver
    message = (
        "Debian's chromium and chromium-driver are not installed "
        "(make test installs them: apt-get install chromium chromium-driver)"
    )
    if os.environ.get("CI") == "true":
        pytest.fail(message + "; the browser tests must run in CI")
    pytest.skip(message)


@contextlib.contextmanager
def headless_chromium(width: int = 1400, height: int = 900) -> Iterator[object]:
    """A selenium WebDriver on headless chromium, quit afterwards."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser, driver_path = chromium_paths()
    options = webdriver.ChromeOptions()
    options.binary_location = browser
    for argument in (
        "--headless=new",
        "--no-sandbox",  # root in a container: the sandbox cannot start
        "--disable-gpu",
        "--disable-dev-shm-usage",
        f"--window-size={width},{height}",
    ):
        options.add_argument(argument)
    driver = webdriver.Chrome(service=Service(driver_path), options=options)
    try:
        yield driver
    finally:
        driver.quit()
