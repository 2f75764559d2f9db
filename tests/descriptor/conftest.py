"""Fixtures of the descriptor tests: the samples read once, and their descriptors."""

from __future__ import annotations

import pytest

from acordcs.descriptor import Application
from acordcs.generator.describe import describe
from acordcs.model.reading import ModelReading, read_model
from tests.support.toolchain import SMARTROOM, WEBLAB


@pytest.fixture(scope="session")
def weblab_reading() -> ModelReading:
    reading = read_model(str(WEBLAB))
    assert reading.worst() is None, reading.diagnostics
    return reading


@pytest.fixture(scope="session")
def weblab(weblab_reading: ModelReading) -> Application:
    return describe(weblab_reading.architecture)


@pytest.fixture(scope="session")
def smartroom() -> Application:
    reading = read_model(str(SMARTROOM))
    assert reading.worst() is None, reading.diagnostics
    return describe(reading.architecture)
