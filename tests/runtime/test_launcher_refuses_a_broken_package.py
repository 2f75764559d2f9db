"""A container does not start from a broken package, and says where it is broken without a
traceback (exit 2): a descriptor.xml that fails its schema or declares entities (file, line and
column), component code that does not parse or import (file and line)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.support.generator import build, run_container
from tests.support.toolchain import WEBLAB

REMOTE = ("--remote", "UserSide=PYRO:acordcs.container.UserSide@127.0.0.1:9")


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("broken") / "out"
    assert build(WEBLAB, out, "-t", "python").code == 0
    return out


@pytest.fixture
def package(built: Path, tmp_path: Path) -> Path:
    out = tmp_path / "out"
    shutil.copytree(built, out)
    return out


def refused(package: Path, *args: str) -> list[str]:
    done = run_container(package, "weblab_app.WebLabSide", *REMOTE, *args)
    assert done.returncode == 2, done.stdout + done.stderr
    assert "Traceback" not in done.stderr and done.stdout == ""
    return done.stderr.splitlines()


def position(text: str, part: str) -> tuple[int, int]:
    """Line and column (1-based) of ``part`` in ``text``."""
    before = text[: text.index(part)]
    return before.count("\n") + 1, len(before) - (before.rfind("\n") + 1) + 1


def test_a_descriptor_that_fails_its_schema(package: Path) -> None:
    path = package / "weblab_app" / "descriptor.xml"
    text = path.read_text(encoding="utf-8").replace(' host="weblab.example.org">', ">", 1)
    path.write_text(text, encoding="utf-8")
    line, column = position(text, '<container id="BOUML_0x20582_4"')
    lines = refused(package)
    assert lines[0] == (
        f"python -m weblab_app.WebLabSide: {path}:{line}:{column}: error: does not validate "
        "against acordcs-descriptor.xsd: Element 'container': The attribute 'host' is required "
        "but missing. (a descriptor follows acordcs-descriptor.xsd (shipped in "
        "acordcs/descriptor); write it with acordcs.descriptor.to_xml from the model rather "
        "than by hand)"
    )
    assert lines[1] == (
        "python -m weblab_app.WebLabSide: the package's descriptor is refused: rebuild the "
        "package (acordcs-gen build)"
    )


def test_a_descriptor_declaring_entities(package: Path) -> None:
    path = package / "weblab_app" / "descriptor.xml"
    text = path.read_text(encoding="utf-8")
    bomb = '<!DOCTYPE a [<!ENTITY x "xxxxxxxxxx"><!ENTITY y "&x;&x;&x;&x;&x;&x;&x;&x;">]>\n'
    path.write_text(text.replace("<application", bomb + "<application", 1), encoding="utf-8")
    (first, *_) = refused(package)
    assert first.startswith(f"python -m weblab_app.WebLabSide: {path}:")
    assert "a descriptor has no document type or entity declarations" in first


def test_component_code_that_does_not_parse(package: Path) -> None:
    path = package / "weblab_app" / "components" / "Vision.py"
    path.write_text("x = (\n", encoding="utf-8")
    (line,) = refused(package)
    assert line.startswith(f"python -m weblab_app.WebLabSide: {path}:1:5: error: ")
    assert line.endswith(": fix the syntax there")


def test_component_code_that_does_not_import(package: Path) -> None:
    path = package / "weblab_app" / "components" / "Vision.py"
    path.write_text('"""Vision."""\n\nimport no_such_module_here\n', encoding="utf-8")
    (line,) = refused(package)
    assert line == (
        f"python -m weblab_app.WebLabSide: {path}:3: error: importing the application's "
        "classes failed: ModuleNotFoundError: No module named 'no_such_module_here': fix the "
        "code there (components/ and monitors/ are yours; a generated file that is missing or "
        "stale: acordcs-gen build)"
    )
