"""Fixtures and hooks shared by the test tree (helpers live in tests/support/)."""

from __future__ import annotations

import os

import pytest
from hypothesis import settings

from tests.support.toolchain import WEBLAB, MissingReference

# In CI the property tests draw the same examples on every run (derandomize), so that a run fails
# only for a change, never for a draw; outside CI they draw afresh, to find what CI would not. A
# failure prints the example and the blob that reproduces it (@reproduce_failure).
settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("dev", print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") == "true" else "dev")


@pytest.fixture(scope="session")
def weblab_text() -> str:
    return WEBLAB.read_text(encoding="utf-8")


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_call(item: pytest.Item) -> None:
    """A test parametrised with a :class:`MissingReference` (its folder of real exports is absent)
    is skipped, or failed when CI=true, with the reason, instead of running on the placeholder."""
    callspec = getattr(item, "callspec", None)
    for value in callspec.params.values() if callspec else ():
        if isinstance(value, MissingReference):
            value.refuse()
