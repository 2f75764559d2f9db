"""The WebLab simulator's tests: ``samples/weblab`` on sys.path (for ``weblab_sim``), and the
application generated from ``weblab.xmi`` built into ``samples/weblab/app`` (where its component
code lives) once per session, as ``make demo`` builds it; a no-op when it is up to date."""

from __future__ import annotations

import sys

import pytest

from acordcs.cli import main
from tests.support.toolchain import WEBLAB

SAMPLE_DIR = WEBLAB.parent
APP_DIR = SAMPLE_DIR / "app"
if str(SAMPLE_DIR) not in sys.path:
    sys.path.insert(0, str(SAMPLE_DIR))


@pytest.fixture(scope="session")
def weblab_app() -> None:
    """The generated application, built (or found up to date) in samples/weblab/app."""
    assert main(["build", str(WEBLAB), "-o", str(APP_DIR)]) == 0
