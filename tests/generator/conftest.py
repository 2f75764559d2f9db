"""Fixtures of the generator tests (helpers live in gen_helpers.py)."""

from __future__ import annotations

import pytest
from gen_helpers import WEBLAB


@pytest.fixture(scope="session")
def weblab_text() -> str:
    return WEBLAB.read_text(encoding="utf-8")
