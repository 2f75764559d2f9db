"""Fixtures of the generator tests: the samples' readings and descriptors, read once."""

from __future__ import annotations

import pytest

from acordcs.descriptor import Application
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from tests.support.toolchain import SMARTROOM, WEBLAB


def _describe(path) -> Application:
    reading = read_model(str(path))
    assert reading.worst() is None, reading.diagnostics
    return describe(reading.architecture)


@pytest.fixture(scope="session")
def weblab() -> Application:
    return _describe(WEBLAB)


@pytest.fixture(scope="session")
def smartroom() -> Application:
    return _describe(SMARTROOM)
