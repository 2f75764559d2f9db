"""A generated file edited since the build that wrote it is not silently overwritten: the build
saves the user's version as ``<file>.edited`` (``.edited.2``... when taken) before regenerating it,
and says so by name. In ``bin/env.sh`` the lines between ``BEGIN USER``/``END USER`` markers are the
user's (kept, as ever); an edit outside them is saved the same way. ``--check`` and ``--dry-run``
say what would be saved and save nothing."""

from __future__ import annotations

from pathlib import Path

from tests.support.generator import build, snapshot
from tests.support.toolchain import WEBLAB

BASE = "weblab_app/base/Locomotion.py"


def test_an_edited_generated_file_is_saved_then_regenerated(tmp_path: Path):
    assert build(WEBLAB, tmp_path).code == 0
    fresh = (tmp_path / BASE).read_bytes()
    edited = fresh.replace(b"raise OperationNotImplementedError(", b"return 42  # (", 1)
    (tmp_path / BASE).write_bytes(edited)
    result = build(WEBLAB, tmp_path)
    assert result.code == 0, result.both
    assert (tmp_path / BASE).read_bytes() == fresh
    assert (tmp_path / (BASE + ".edited")).read_bytes() == edited
    assert (
        f"acordcs-gen: {tmp_path}/{BASE}: was edited since the build that wrote it: your version "
        f"is saved as {tmp_path}/{BASE}.edited, and the file regenerated"
    ) in result.err
    assert f"wrote {tmp_path}/{BASE}.edited" in result.out
    # the .edited file is the user's: the next build leaves it, and a no-op rebuild stays a no-op
    again = build(WEBLAB, tmp_path)
    assert "up to date" in again.out and (tmp_path / (BASE + ".edited")).read_bytes() == edited


def test_a_second_edit_does_not_replace_the_first_saved_one(tmp_path: Path):
    build(WEBLAB, tmp_path)
    (tmp_path / BASE).write_text("first edit\n", encoding="utf-8")
    build(WEBLAB, tmp_path)
    (tmp_path / BASE).write_text("second edit\n", encoding="utf-8")
    result = build(WEBLAB, tmp_path)
    assert result.code == 0
    assert (tmp_path / (BASE + ".edited")).read_text(encoding="utf-8") == "first edit\n"
    assert (tmp_path / (BASE + ".edited.2")).read_text(encoding="utf-8") == "second edit\n"
    # the same edit a third time is already saved: nothing new
    (tmp_path / BASE).write_text("second edit\n", encoding="utf-8")
    result = build(WEBLAB, tmp_path)
    assert not (tmp_path / (BASE + ".edited.3")).exists()
    assert f"saved as {tmp_path}/{BASE}.edited.2" in result.err


def test_check_and_dry_run_say_what_would_be_saved_and_save_nothing(tmp_path: Path):
    build(WEBLAB, tmp_path)
    (tmp_path / BASE).write_text("mine\n", encoding="utf-8")
    before = snapshot(tmp_path)
    for flag in ("--check", "--dry-run"):
        result = build(WEBLAB, tmp_path, flag)
        assert result.code == (1 if flag == "--check" else 0), result.both
        assert f"your version would be saved as {tmp_path}/{BASE}.edited" in result.err
        assert snapshot(tmp_path) == before


def _env(out: Path) -> str:
    return (out / "bin" / "env.sh").read_text(encoding="utf-8")


def test_env_sh_lines_outside_its_regions_are_saved_inside_them_kept(tmp_path: Path):
    build(WEBLAB, tmp_path)
    text = _env(tmp_path)
    begin = next(line for line in text.splitlines() if line.startswith("# BEGIN USER "))
    inside = text.replace(begin + "\n", begin + "\nexport MINE=1\n", 1)
    (tmp_path / "bin" / "env.sh").write_text(inside, encoding="utf-8")
    result = build(WEBLAB, tmp_path, "--force")
    assert result.code == 0
    assert _env(tmp_path) == inside  # a region's lines are the user's: nothing to save
    assert not (tmp_path / "bin" / "env.sh.edited").exists() and "edited" not in result.err

    outside = inside + "export OUTSIDE=1\n"
    (tmp_path / "bin" / "env.sh").write_text(outside, encoding="utf-8")
    result = build(WEBLAB, tmp_path)
    assert result.code == 0, result.both
    assert _env(tmp_path) == inside  # regenerated, the region's line kept
    assert (tmp_path / "bin" / "env.sh.edited").read_text(encoding="utf-8") == outside
    assert (
        f"{tmp_path}/bin/env.sh: lines outside its BEGIN USER/END USER regions were edited since "
        "the build that wrote it"
    ) in result.err
