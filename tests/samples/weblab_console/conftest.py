"""The WebLab's hand-written packages (weblab_console) live in samples/weblab, not in acordcs."""

from __future__ import annotations

import sys

import pytest

from acordcs.cli import main
from tests.support.toolchain import ROOT, WEBLAB

WEBLAB_DIR = str(ROOT / "samples" / "weblab")
if WEBLAB_DIR not in sys.path:
    sys.path.insert(0, WEBLAB_DIR)


@pytest.fixture(scope="session")
def weblab_app() -> None:
    """The generated WebLab application, built (or found up to date) in samples/weblab/app, as
    ``make console`` builds it: the console's session runs it."""
    assert main(["build", str(WEBLAB), "-o", str(ROOT / "samples" / "weblab" / "app")]) == 0
