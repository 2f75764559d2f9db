"""``validate`` refuses the names ``build`` cannot generate (G701, G703), with the same diagnostic
``build`` prints: a model the validate hook passes is one the build hook can build. A component
named ``__init__`` gets a diagnostic, not Saxon's XTDE1490 reported as a fault of a stylesheet."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.support.generator import build, weblab_variant
from tests.support.toolchain import no_crash, run_main

LONG = "A" * 230


@pytest.mark.parametrize(
    ("element", "name", "code", "says"),
    [
        ("Access", "CON", "G701", "'CON' is a device name on Windows"),
        ("Access", "nul", "G701", "'nul' is a device name on Windows"),
        ("Access", LONG, "G701", "longer than 200 bytes"),
        ("Access", "__init__", "G703", "base/__init__.py and components/__init__.py"),
        ("UserSide", "registry", "G703", "its module registry.py would be a module of the"),
        ("UserSide", "__init__", "G703", "its module __init__.py would be a module of the"),
        ("UserSide", "Components", "G703", "its module Components.py would be a module of the"),
    ],
)
def test_validate_refuses_what_build_refuses(
    tmp_path: Path, element: str, name: str, code: str, says: str
):
    model = weblab_variant(tmp_path, (f'name="{element}" xmi:id', f'name="{name}" xmi:id'))
    checked = run_main(["validate", str(model)])
    no_crash(checked)
    assert checked.code == 1, checked.both
    found = [line for line in checked.out.splitlines() if f": error: {code} " in line]
    assert len(found) == 1 and says in found[0], checked.out
    built = build(model, tmp_path / "out")
    no_crash(built)
    assert built.code == 1
    assert found[0] in built.out.splitlines()  # the same diagnostic, the same line
    assert "XTDE1490" not in built.both and "stylesheet" not in built.err
    assert not (tmp_path / "out").exists()


def test_an_operation_starting_with_underscore_and_a_parameter_self(tmp_path: Path):
    model = weblab_variant(
        tmp_path,
        ('name="move" xmi:id', 'name="_move" xmi:id'),
        ('name="speed" xmi:id="BOUML_op_param_2"', 'name="self" xmi:id="BOUML_op_param_2"'),
    )
    checked = run_main(["validate", str(model)])
    assert checked.code == 1
    assert "G703 operation '_move' cannot be written into the generated Python files" in checked.out
    assert "G703 parameter 'self' cannot be written into the generated Python files" in checked.out
