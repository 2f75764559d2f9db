"""Fixtures and hooks shared by the test tree (helpers live in tests/support/)."""

from __future__ import annotations

import pytest

from tests.support.toolchain import WEBLAB, MissingReference


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
