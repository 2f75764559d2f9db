"""One headless chromium for every browser test of the console (its start is the costliest step
on a loaded host)."""

from __future__ import annotations

import pytest

from tests.support.browser import chromium_driver


@pytest.fixture(scope="session")
def chromium():
    driver = chromium_driver(1400, 1300)
    try:
        yield driver
    finally:
        driver.quit()
