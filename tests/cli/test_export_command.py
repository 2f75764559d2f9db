"""``acordcs-gen export MODEL -o FILE``: the model as an instance of ``acordcs.ecore`` with the
metamodel beside it; a model with errors, an unreadable model or an unwritable place writes
nothing and leaves what was there; a file that would not change is not written again.

That EMF itself loads what is written is tests/emf's test_exported_model_loads_in_emf_by_its_schema_location.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from lxml import etree

from acordcs import metamodel
from tests.support.toolchain import (
    WEBLAB,
    entry_point,
    no_crash,
    replace,
    run_main,
    run_process,
)

XSI = "{http://www.w3.org/2001/XMLSchema-instance}"


def test_writes_the_instance_and_the_metamodel_beside_it(tmp_path: Path) -> None:
    out = tmp_path / "made" / "weblab.acordcs.xmi"
    result = run_main(["export", str(WEBLAB), "-o", str(out)])
    no_crash(result)
    assert result.code == 0, result.both
    assert result.out.splitlines() == [
        f"wrote {out} (an instance of acordcs.ecore: 2 containers, 6 components, 6 connections, "
        "3 monitors, 3 policy sets)",
        f"wrote {tmp_path / 'made' / 'acordcs.ecore'} (the metamodel {out} names in "
        "xsi:schemaLocation: keep the two files together)",
    ]
    root = etree.parse(str(out)).getroot()
    assert root.tag == f"{{{metamodel.NS_URI}}}Application" and root.get("name") == "WebLab"
    assert root.get(f"{XSI}schemaLocation") == f"{metamodel.NS_URI} acordcs.ecore"
    beside = (tmp_path / "made" / "acordcs.ecore").read_bytes()
    assert beside == Path(metamodel.ecore_path()).read_bytes()
    # a rule's label is its own feature, the text without it
    rule = root.find("policySets/policies/rules[@label='smallNarrow']")
    assert rule is not None and rule.get("text") == (
        "if cycleRate is small and angle is narrow then Locomotion.maxSpeed is slow"
    )
    assert oct(out.stat().st_mode & 0o777) == oct(0o666 & ~_umask())


def test_a_second_export_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "weblab.acordcs.xmi"
    assert run_main(["export", str(WEBLAB), "-o", str(out)]).code == 0
    before = {p: p.stat().st_mtime_ns for p in tmp_path.iterdir()}
    os.utime(out, ns=(1, 1))
    again = run_main(["export", str(WEBLAB), "-o", str(out)])
    assert again.code == 0
    assert [line.split(" ")[:3] for line in again.out.splitlines()] == [
        ["up", "to", "date:"],
        ["up", "to", "date:"],
    ]
    assert out.stat().st_mtime_ns == 1  # not rewritten
    assert set(tmp_path.iterdir()) == set(before)  # no temporary file left


def test_a_model_with_errors_writes_nothing_and_keeps_the_old_file(tmp_path: Path) -> None:
    text = WEBLAB.read_text(encoding="utf-8")
    broken = tmp_path / "broken.xmi"
    # both places BOUML writes the tag: the element's extension and the root-level application
    broken.write_text(
        replace(text, "smallNarrow: if cycleRate is", "smallNarrow: if cycleRat is", count=2),
        encoding="utf-8",
    )
    out = tmp_path / "out.xmi"
    out.write_bytes(b"the previous export")
    result = run_main(["export", str(broken), "-o", str(out)])
    no_crash(result)
    assert result.code == 1, result.both
    assert "L402" in result.out and f"{broken}: 1 error, 0 warnings" in result.out
    assert "has 1 error: nothing written" in result.err
    assert out.read_bytes() == b"the previous export"
    assert not (tmp_path / "acordcs.ecore").exists()


def test_hostile_names_are_written_as_data(tmp_path: Path) -> None:
    hostile = 'Web<Lab> & "x" \u202eevil\nline <!-- --> ]]>'
    quoted = (
        hostile.replace("&", "&amp;")
        .replace("<", "&lt;")
        .replace(">", "&gt;")
        .replace('"', "&quot;")
        .replace("\n", "&#10;")
    )
    model = tmp_path / "hostile.xmi"
    model.write_text(
        replace(WEBLAB.read_text(encoding="utf-8"), 'name="WebLab">', f'name="{quoted}">'),
        encoding="utf-8",
    )
    out = tmp_path / "out.xmi"
    result = run_main(["export", str(model), "-o", str(out)])
    assert result.code == 0, result.both
    root = etree.parse(str(out)).getroot()
    assert root.get("name") == hostile
    assert [e.tag for e in root.iter(etree.Comment)] == []  # no markup came from the name


def test_an_unreadable_model_exits_2(tmp_path: Path) -> None:
    result = run_main(["export", str(tmp_path / "missing.xmi"), "-o", str(tmp_path / "o.xmi")])
    no_crash(result)
    assert result.code == 2 and "X101" in result.out
    assert list(tmp_path.iterdir()) == []


def test_a_foreign_acordcs_ecore_beside_is_not_replaced(tmp_path: Path) -> None:
    foreign = tmp_path / "acordcs.ecore"
    foreign.write_text("<mine/>", encoding="utf-8")
    result = run_main(["export", str(WEBLAB), "-o", str(tmp_path / "w.xmi")])
    no_crash(result)
    assert result.code == 2
    assert result.err == (
        f"acordcs-gen export: {foreign}: error: is not the ACORD-CS metamodel (no nsURI "
        f"{metamodel.NS_URI}); not replaced, nothing written (move it away, or export into "
        "another directory)\n"
    )
    assert foreign.read_text(encoding="utf-8") == "<mine/>"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["acordcs.ecore"]


def test_an_older_acordcs_ecore_beside_is_replaced(tmp_path: Path) -> None:
    shipped = Path(metamodel.ecore_path()).read_text(encoding="utf-8")
    older = tmp_path / "acordcs.ecore"
    older.write_text(shipped.replace('name="PortKind"', 'name="PortKinds"'), encoding="utf-8")
    assert run_main(["export", str(WEBLAB), "-o", str(tmp_path / "w.xmi")]).code == 0
    assert older.read_text(encoding="utf-8") == shipped


@pytest.mark.parametrize(
    ("output", "message"),
    [
        ("acordcs.ecore", "the instance file cannot be named acordcs.ecore"),
        ("a-file/w.xmi", "cannot be written"),
    ],
)
def test_places_it_cannot_write_exit_2(tmp_path: Path, output: str, message: str) -> None:
    (tmp_path / "a-file").write_text("not a directory", encoding="utf-8")
    result = run_main(["export", str(WEBLAB), "-o", str(tmp_path / output)])
    no_crash(result)
    assert result.code == 2 and message in result.err, result.both
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


def test_standard_input_and_the_installed_executable(tmp_path: Path) -> None:
    out = tmp_path / "w.xmi"
    with open(WEBLAB, "rb") as model:
        done = subprocess.run(
            [*entry_point(), "export", "-", "-o", str(out)],
            stdin=model,
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
    assert done.returncode == 0, done.stdout + done.stderr
    assert etree.parse(str(out)).getroot().get("name") == "WebLab"
    usage = run_process(["export", str(WEBLAB)])
    assert usage.code == 2 and "Missing option '-o'" in usage.err


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
