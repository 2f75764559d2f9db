"""The WebLab's hand-written packages (weblab_console) live in samples/weblab, not in acordcs."""

from __future__ import annotations

import sys

from tests.support.toolchain import ROOT

WEBLAB_DIR = str(ROOT / "samples" / "weblab")
if WEBLAB_DIR not in sys.path:
    sys.path.insert(0, WEBLAB_DIR)
