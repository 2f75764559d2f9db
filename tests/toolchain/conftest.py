"""Fixtures of the generator tests (helpers live in tests/support/toolchain.py)."""

from __future__ import annotations

import pytest

from tests.support.toolchain import WEBLAB


@pytest.fixture(scope="session")
def weblab_text() -> str:
    return WEBLAB.read_text(encoding="utf-8")
