"""What ``acordcs-gen update`` says before it applies a model (acordcs.runtime.live.code_check's
``operations_without_code_in_files``: the user's files read, not imported) is what the container
would say at start (``operations_without_code``, on the classes imported): on a fresh WebLab build
(every operation its model calls, with their callers: policy sets, polling monitors, connections
to synchronous ports), on the WebLab's own code (nothing), and after an operation is renamed in
the model (``countUsers`` to ``sampleUsers``: the monitor that polls it and the connection that
reaches it, in the same words, at the class's line). A class deriving from another class than
its generated base is not judged."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from acordcs.descriptor import from_xml
from acordcs.runtime.api import VirtualClock
from acordcs.runtime.live.code_check import (
    operations_without_code,
    operations_without_code_in_files,
)
from tests.runtime.test_operations_without_code_are_listed_at_start import CALLED, with_weblab_code
from tests.support.generator import build, imported, weblab_variant
from tests.support.toolchain import WEBLAB

URI = "PYRO:acordcs.container.{}@127.0.0.1:9"


def both(out: Path, container: str) -> tuple[list[str], list[str]]:
    """(what the files say, what the imported classes say) for ``container`` of ``out``."""
    app = from_xml((out / "weblab_app" / "descriptor.xml").read_bytes())
    files = [
        m.message(out) for m in operations_without_code_in_files(app, container, out, "weblab_app")
    ]
    other = "UserSide" if container == "WebLabSide" else "WebLabSide"
    with (
        imported(out, "weblab_app") as package,
        package.assemble_application(
            only=[container], remote={other: URI.format(other)}, clock=VirtualClock()
        ) as running,
    ):
        classes = [m.message(out) for m in operations_without_code(running, container)]
    return files, classes


def test_a_fresh_build_says_what_a_start_says(tmp_path: Path) -> None:
    assert build(WEBLAB, tmp_path, "-t", "python").code == 0
    app = from_xml((tmp_path / "weblab_app" / "descriptor.xml").read_bytes())
    found = operations_without_code_in_files(app, "WebLabSide", tmp_path, "weblab_app")
    assert [(m.component, m.operation, m.callers) for m in found] == CALLED
    files, classes = both(tmp_path, "WebLabSide")
    assert files == classes
    assert both(tmp_path, "UserSide") == ([], [])


@pytest.fixture
def weblab_path():
    sys.path.insert(0, str(WEBLAB.parent))  # weblab_sim, which the WebLab's code imports
    yield
    sys.path.remove(str(WEBLAB.parent))


def test_the_weblabs_own_code_says_nothing(tmp_path: Path, weblab_path) -> None:
    out = with_weblab_code(tmp_path / "out")
    assert build(WEBLAB, out, "-t", "python").code == 0
    assert both(out, "WebLabSide") == ([], [])


def test_a_renamed_operation_is_said_with_its_callers_at_the_class(tmp_path, weblab_path) -> None:
    out = with_weblab_code(tmp_path / "out")
    model = weblab_variant(tmp_path, ('"countUsers"', '"sampleUsers"', 3))
    assert build(model, out, "-t", "python").code == 0
    files, classes = both(out, "WebLabSide")
    assert files == classes
    source = (out / "weblab_app" / "components" / "Access.py").read_text(encoding="utf-8")
    line = source.splitlines().index("class Access(AccessBase):") + 1
    assert files == [
        f"weblab_app/components/Access.py:{line}: warning: Access.sampleUsers() has no code, and "
        "monitor Usage polls it; connection AccessLink reaches it from Navigator.NavAccessPort: "
        "implement sampleUsers() in class Access (each call raises OperationNotImplementedError "
        "until then)"
    ]


def test_a_class_with_other_bases_is_not_judged(tmp_path: Path) -> None:
    assert build(WEBLAB, tmp_path, "-t", "python").code == 0
    path = tmp_path / "weblab_app" / "components" / "Vision.py"
    path.write_text(
        "from weblab_app.base.Vision import VisionBase\n\n\nclass Grabbing:\n"
        "    def grab(self):\n        return b''\n\n\nclass Vision(Grabbing, VisionBase):\n"
        "    pass\n",
        encoding="utf-8",
    )
    app = from_xml((tmp_path / "weblab_app" / "descriptor.xml").read_bytes())
    found = operations_without_code_in_files(app, "WebLabSide", tmp_path, "weblab_app")
    assert "Vision" not in {m.component for m in found}
    assert "Access" in {m.component for m in found}
