"""Drift between the model and the user's classes, found by the build (issue 21): in a copy of each
sample, renaming an operation, a port and a component while their ids stay, or removing an
operation, gives a G704 warning in the user's file, at the method's line, with the new name;
``--strict`` makes any of them exit 1 (and ``--check --strict`` in CI), and the warning stays
while the class implements the old name."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from acordcs.descriptor import from_xml
from tests.support.generator import build
from tests.support.toolchain import SAMPLES, SMARTROOM, WEBLAB

APP = SAMPLES / "weblab" / "app" / "weblab_app"


def _copy(model: Path, tmp_path: Path) -> Path:
    path = tmp_path / model.name
    shutil.copy(model, path)
    return path


def _edit(path: Path, old: str, new: str, count: int = 1) -> None:
    text = path.read_text(encoding="utf-8")
    assert text.count(old) == count, (old, text.count(old))
    path.write_text(text.replace(old, new), encoding="utf-8")


def _g704(out: str) -> list[tuple[str, int, str]]:
    """(file, line, message) of each G704 warning."""
    return [
        (m.group(1), int(m.group(2)), m.group(3))
        for m in re.finditer(r"^(\S+?):(\d+):\d+: warning: G704 (.*)$", out, flags=re.M)
    ]


@pytest.fixture
def weblab(tmp_path: Path) -> tuple[Path, Path]:
    """A copy of the WebLab model built once into ``out``, with the WebLab's own classes."""
    model, out = _copy(WEBLAB, tmp_path), tmp_path / "out"
    shutil.copytree(APP / "components", out / "weblab_app" / "components")
    assert build(model, out, "-t", "python").code == 0
    return model, out


def test_a_renamed_operation_names_the_method_and_the_new_name(weblab):
    model, out = weblab
    _edit(model, '"countUsers"', '"sampleUsers"', 3)  # the operation, the polling monitor's tags
    result = build(model, out, "-t", "python")
    assert result.code == 0  # a warning
    (found,) = _g704(result.out)
    access = out / "weblab_app" / "components" / "Access.py"
    line = access.read_text(encoding="utf-8").splitlines().index("    def countUsers(self) -> int:")
    assert found[:2] == (str(access), line + 1)
    assert "method countUsers() of class Access implements operation countUsers, which the model "
    assert "now names sampleUsers" in found[2] and "rename the method to sampleUsers" in found[2]
    assert build(model, out, "-t", "python", "--strict").code == 1
    # built again, the history is gone but the class still has the old name: still told
    again = build(model, out, "-t", "python", "--check", "--strict")
    assert again.code == 1
    ((_, _, message),) = _g704(again.out)
    assert "operation sampleUsers of component Access has no code" in message
    assert "countUsers() (line" in message
    # renamed in the class too: nothing more to say
    _edit(access, "def countUsers(self)", "def sampleUsers(self)")
    fixed = build(model, out, "-t", "python", "--check", "--strict")
    assert _g704(fixed.out) == [] and fixed.code == 0


def test_a_removed_operation_says_so(weblab):
    model, out = weblab
    text = model.read_text(encoding="utf-8")
    start = text.index('<ownedOperation xmi:type="uml:Operation" name="countUsers"')
    end = text.index("</ownedOperation>", start) + len("</ownedOperation>")
    model.write_text(text[:start] + text[end:], encoding="utf-8")
    _edit(model, 'acquisition="poll" xpath="" operation="countUsers" frequency="1"',
          'acquisition="custom" xpath="" operation="" frequency="1"')  # fmt: skip
    _edit(model, 'CtxMonitor:acquisition" value="poll"', 'CtxMonitor:acquisition" value="custom"')
    _edit(model, 'CtxMonitor:operation" value="countUsers"', 'CtxMonitor:operation" value=""')
    result = build(model, out, "-t", "python")
    assert result.code == 0, result.out
    ((_, _, message),) = _g704(result.out)
    assert "implements operation countUsers" in message
    assert "which is no longer in the model: remove the method" in message


def test_a_renamed_port_names_its_handler(weblab):
    model, out = weblab
    vision = out / "weblab_app" / "components" / "Vision.py"
    with vision.open("a", encoding="utf-8") as handle:
        handle.write("\n    def on_VisionPort(self, message: object) -> None:\n        pass\n")
    build(model, out, "-t", "python")  # the descriptor this code was written against
    _edit(model, 'name="VisionPort"', 'name="SightPort"')
    result = build(model, out, "-t", "python")
    ((path, line, message),) = _g704(result.out)
    assert path == str(vision) and "def on_VisionPort" in vision.read_text().splitlines()[line - 1]
    assert "handles port VisionPort, which the model now names SightPort" in message
    assert "rename the method to on_SightPort" in message


def test_a_renamed_component_says_where_its_code_is_and_what_to_move(weblab):
    model, out = weblab
    _edit(model, '<packagedElement xmi:type="uml:Class" name="Vision" ',
          '<packagedElement xmi:type="uml:Class" name="Eyes" ')  # fmt: skip
    result = build(model, out, "-t", "python")
    ((path, _, message),) = _g704(result.out)
    assert path == str(out / "weblab_app" / "components" / "Vision.py")
    assert "is your code for component Vision, which the model now names Eyes" in message
    assert "move your code into weblab_app/components/Eyes.py (class Eyes" in message
    assert "no longer in the model: kept" not in result.err  # the warning says it all
    assert (out / "weblab_app" / "components" / "Vision.py").is_file()  # nothing lost


def test_the_smartroom_too(tmp_path: Path):
    model, out = _copy(SMARTROOM, tmp_path), tmp_path / "out"
    assert build(model, out, "-t", "python").code == 0
    app = from_xml((out / "smartroom_app" / "descriptor.xml").read_bytes())
    lights = next(c for c in app.components if c.name == "Lights")
    (level,) = [op for op in lights.operations if op.name == "setLevel"]
    user = out / "smartroom_app" / "components" / "Lights.py"
    user.write_text(
        user.read_text(encoding="utf-8").replace(
            "    pass\n", "    def setLevel(self, level: float) -> None:\n        pass\n"
        ),
        encoding="utf-8",
    )
    _edit(model, 'name="setLevel"', 'name="dim"')
    result = build(model, out, "-t", "python", "--strict")
    assert result.code == 1
    ((path, _, message),) = _g704(result.out)
    assert path == str(user) and f"now names dim (id {level.id})" in message
