"""``--check`` (exit 1 when the output is not up to date), ``--dry-run`` (what would be written or
deleted) and ``--diff`` (a unified diff of what would change) write nothing."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.support.generator import FASTER, build, snapshot, weblab_variant
from tests.support.toolchain import WEBLAB


@pytest.mark.parametrize("option", ["--check", "--dry-run", "--diff"])
def test_nothing_is_written_to_an_empty_output(tmp_path: Path, option: str):
    out = tmp_path / "out"
    result = build(WEBLAB, out, option)
    assert result.code == (1 if option == "--check" else 0), result.both
    assert not out.exists()


def test_check_exits_1_until_built_then_0(tmp_path: Path):
    result = build(WEBLAB, tmp_path, "--check")
    assert result.code == 1
    assert f"{tmp_path}: not up to date: 59 files to write, 0 to delete" in result.err
    assert build(WEBLAB, tmp_path).code == 0
    result = build(WEBLAB, tmp_path, "--check")
    assert result.code == 0 and "up to date" in result.out
    result = build(WEBLAB, tmp_path, "--check", "--force")  # the model read and transformed
    assert result.code == 0 and "up to date (59 files)" in result.out


def test_check_after_a_model_change(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    before = snapshot(out)
    result = build(weblab_variant(tmp_path, FASTER), out, "--check")
    assert result.code == 1
    assert "not up to date: 3 files to write, 0 to delete" in result.err
    assert snapshot(out) == before


def test_dry_run_lists_writes_and_deletes(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    before = snapshot(out)
    renamed = weblab_variant(tmp_path, ('name="BandwidthLimiting"', 'name="FrameLimiting"'))
    result = build(renamed, out, "--dry-run")
    assert result.code == 0
    assert result.out.splitlines() == [
        f"would write {out}/WebLab.descriptor.xml",
        f"would delete {out}/rules/BandwidthLimiting.fcl",
        f"would write {out}/rules/FrameLimiting.fcl",
        f"would write {out}/weblab_app/WebLabSide.py",  # its docstring lists what it hosts
        # the bases of the monitors feeding the set name it in their docstrings
        f"would write {out}/weblab_app/base/Control.py",
        f"would write {out}/weblab_app/base/Usage.py",
        f"would write {out}/weblab_app/descriptor.xml",
        f"{out}: not up to date: 6 files to write, 1 to delete",
    ]
    assert snapshot(out) == before


def test_diff_shows_the_changed_lines(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    before = snapshot(out)
    result = build(weblab_variant(tmp_path, FASTER), out, "--diff")
    assert result.code == 0
    lines = result.out.splitlines()
    assert "--- a/rules/SpeedLimiting.fcl" in lines and "+++ b/rules/SpeedLimiting.fcl" in lines
    old = "    RULE largeNarrow : IF Control_cycleRate IS large AND Control_angle IS narrow THEN "
    assert f"-{old}Locomotion_maxSpeed IS fast;" in lines
    assert f"+{old}Locomotion_maxSpeed IS medium;" in lines
    assert snapshot(out) == before


def test_diff_of_a_new_file_is_against_dev_null(tmp_path: Path):
    result = build(WEBLAB, tmp_path / "out", "--diff", "--target", "rules")
    assert "--- /dev/null" in result.out and "+++ b/rules/Recovering.clp" in result.out
