"""Every command reads a model in the notation (a name ending in .acord) as it reads XMI, through
the one reading path: validate, inspect, export and build give what they give for the XMI."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from tests.support.toolchain import ROOT, SAMPLES, entry_point, run_main

TEXT = SAMPLES / "tutorial" / "greenhouse.acord"
PAPYRUS = SAMPLES / "tutorial" / "greenhouse.uml"
_MODEL_FILE = re.compile(r"greenhouse\.(acord|uml)")


@pytest.fixture(scope="module")
def builds(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The greenhouse built from its text and from its Papyrus file, once for the module."""
    out = tmp_path_factory.mktemp("builds")
    for model, name in ((TEXT, "from-text"), (PAPYRUS, "from-papyrus")):
        result = run_main(["build", str(model), "-o", str(out / name)])
        assert result.code == 0, result.both
    return out / "from-text", out / "from-papyrus"


def test_build_writes_the_same_application_from_the_text(builds: tuple[Path, Path]) -> None:
    text, papyrus = builds
    written = sorted(p.relative_to(text) for p in text.rglob("*") if p.is_file())
    assert written == sorted(p.relative_to(papyrus) for p in papyrus.rglob("*") if p.is_file())
    for relative in written:
        if relative.name == ".acordcs-manifest.json":
            continue  # its digests are of the files, whose headers name the model file
        a = _MODEL_FILE.sub("MODEL", (text / relative).read_text(encoding="utf-8"))
        b = _MODEL_FILE.sub("MODEL", (papyrus / relative).read_text(encoding="utf-8"))
        assert a == b, relative


def test_validate_reads_the_text() -> None:
    result = run_main(["validate", str(TEXT)])
    assert result.code == 0 and "0 errors, 0 warnings, 0 infos" in result.out


def test_inspect_shows_the_text_as_its_own_dialect() -> None:
    result = run_main(["inspect", str(TEXT)])
    assert result.code == 0
    assert (
        "acord-text" in result.out and "policy set Ventilation: engine fuzzy, 3 rules" in result.out
    )


def test_export_writes_the_same_instance_from_the_text(tmp_path: Path) -> None:
    for model in (TEXT, PAPYRUS):
        result = run_main(["export", str(model), "-o", str(tmp_path / f"{model.suffix[1:]}.xmi")])
        assert result.code == 0, result.both
    text = (tmp_path / "acord.xmi").read_text(encoding="utf-8")
    papyrus = (tmp_path / "uml.xmi").read_text(encoding="utf-8")
    # the instance keeps each element's line in its model file: those differ, nothing else
    strip = re.compile(r' (line|sourceLine)="\d+"')
    assert strip.sub("", text) == strip.sub("", papyrus)


def test_standard_input_is_read_as_the_text_when_it_is_not_xml() -> None:
    result = subprocess.run(
        [*entry_point(), "validate", "-"],
        input=TEXT.read_bytes(),
        capture_output=True,
        cwd=ROOT,
        timeout=60,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert b"<stdin>: 0 errors" in result.stdout


def test_convert_writes_papyrus_with_the_profile_beside_it(tmp_path: Path) -> None:
    result = run_main(["convert", str(TEXT), "-o", str(tmp_path / "g.uml")])
    assert result.code == 0, result.both
    assert (tmp_path / "ACORDCS.profile.uml").is_file()
    check = run_main(["validate", str(tmp_path / "g.uml")])
    assert check.code == 0 and "0 errors, 0 warnings" in check.out  # T321 would warn without it


def test_convert_to_standard_output_is_the_text(tmp_path: Path) -> None:
    result = run_main(["convert", str(PAPYRUS)])
    assert result.code == 0 and result.out == TEXT.read_text(encoding="utf-8")


def test_convert_writes_nothing_when_the_text_has_an_error(tmp_path: Path) -> None:
    bad = tmp_path / "bad.acord"
    bad.write_text(TEXT.read_text(encoding="utf-8").replace("adapts Vent", "adapts Vnt"))
    target = tmp_path / "out.uml"
    target.write_text("kept")
    result = run_main(["convert", str(bad), "-o", str(target)])
    assert result.code == 1 and "M103" in result.out and "nothing written" in result.err
    assert target.read_text() == "kept"
    unreadable = run_main(["convert", str(tmp_path / "missing.acord"), "-o", str(target)])
    assert unreadable.code == 2 and "X101" in unreadable.out


def test_convert_refuses_what_the_text_cannot_say(tmp_path: Path) -> None:
    """A 'rule' starting with '}' would end its block in the text: refused, nothing written."""
    weird = tmp_path / "weird.uml"
    weird.write_text(PAPYRUS.read_text(encoding="utf-8").replace('Rule="cool:', 'Rule="} cool:'))
    result = run_main(["convert", str(weird), "-o", str(tmp_path / "weird.acord")])
    assert result.code == 1 and "starts with '}'" in result.err and "nothing written" in result.err
    assert not (tmp_path / "weird.acord").exists()
