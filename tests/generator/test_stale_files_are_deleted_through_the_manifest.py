"""Generated files the model no longer makes are deleted, and only those: the manifest says which
files a build wrote; a user's own file is never deleted nor overwritten, a stale file the user
edited is left in place, and another target's files survive a build of one target."""

from __future__ import annotations

from pathlib import Path

from acordcs.generator import target
from acordcs.generator.targets import targets
from tests.support.generator import build, registered, snapshot, weblab_variant
from tests.support.toolchain import WEBLAB

RENAMED = ('name="BandwidthLimiting"', 'name="FrameLimiting"')


def test_a_renamed_policy_set_replaces_its_file(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    (out / "notes.txt").write_text("mine", encoding="utf-8")
    (out / "rules" / "mine.fcl").write_text("mine too", encoding="utf-8")
    mine = {p: v for p, v in snapshot(out).items() if "mine" in p or p == "notes.txt"}
    result = build(weblab_variant(tmp_path, RENAMED), out)
    assert result.code == 0, result.both
    after = snapshot(out)
    assert "rules/BandwidthLimiting.fcl" not in after
    assert "rules/FrameLimiting.fcl" in after
    assert {p: after[p] for p in mine} == mine  # bytes and mtime
    assert f"deleted {out}/rules/BandwidthLimiting.fcl" in result.out


def test_a_stale_file_the_user_edited_is_left_and_reported(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    (out / "rules" / "BandwidthLimiting.fcl").write_text("my notes", encoding="utf-8")
    result = build(weblab_variant(tmp_path, RENAMED), out)
    assert result.code == 0
    assert (out / "rules" / "BandwidthLimiting.fcl").read_text(encoding="utf-8") == "my notes"
    assert "BandwidthLimiting.fcl is no longer generated but was edited since" in result.err


def test_a_users_file_where_a_generated_one_goes_is_never_overwritten(tmp_path: Path):
    (tmp_path / "rules").mkdir()
    (tmp_path / "rules" / "SpeedLimiting.fcl").write_text("mine", encoding="utf-8")
    before = snapshot(tmp_path)
    result = build(WEBLAB, tmp_path)
    assert result.code == 1
    assert snapshot(tmp_path) == before  # nothing written at all
    assert "rules/SpeedLimiting.fcl exists and this build did not write it" in result.err
    assert "move your file away, or choose another output directory" in result.err


def test_building_one_target_keeps_the_others_files(tmp_path: Path):
    build(WEBLAB, tmp_path)
    before = snapshot(tmp_path)
    result = build(
        weblab_variant(tmp_path / "..", RENAMED, name="renamed.xmi"), tmp_path, "-t", "config"
    )
    assert result.code == 0, result.both
    after = snapshot(tmp_path)
    assert {p for p in after if p.startswith("rules/")} == {
        p for p in before if p.startswith("rules/")
    }
    assert all(after[p] == before[p] for p in after if p.startswith("rules/"))
    result = build(tmp_path / ".." / "renamed.xmi", tmp_path, "-t", "rules")
    assert "rules/BandwidthLimiting.fcl" not in snapshot(tmp_path)


def test_files_of_a_target_no_longer_installed_are_stale(tmp_path: Path):
    @target("extra", description="one file")
    def extra(context) -> None:
        context.emit("extra.txt", context.header("hash", "the model") + "x\n")

    with registered(extra):
        assert build(WEBLAB, tmp_path).code == 0
        assert (tmp_path / "extra.txt").is_file()
    targets()
    result = build(WEBLAB, tmp_path)
    assert result.code == 0, result.both
    assert not (tmp_path / "extra.txt").exists()


def test_a_manifest_that_cannot_be_trusted_is_ignored(tmp_path: Path):
    outside = tmp_path / "outside.txt"
    outside.write_text("keep me", encoding="utf-8")
    out = tmp_path / "out"
    build(WEBLAB, out)
    manifest = out / ".acordcs-manifest.json"
    text = manifest.read_text(encoding="utf-8")
    # a manifest listing a path outside the directory is refused as a whole, never followed
    manifest.write_text(text.replace('"acordcs-descriptor.xsd"', '"../outside.txt"'), "utf-8")
    result = build(WEBLAB, out)
    assert result.code == 0, result.both  # the files already hold what is made: adopted as is
    assert "is ignored (it lists '../outside.txt': component '..'" in result.err
    assert "so none is deleted or overwritten" in result.err
    assert "nothing changed (59 files up to date)" in result.out
    assert outside.read_text(encoding="utf-8") == "keep me"
    assert "../outside.txt" not in manifest.read_text(encoding="utf-8")  # written anew
    manifest.write_text("{not json", encoding="utf-8")
    (out / "rules" / "SpeedLimiting.fcl").write_text("edited", encoding="utf-8")
    result = build(WEBLAB, out)
    assert result.code == 1  # without a manifest, the edited file is not known to be ours
    assert "is ignored (it is not a manifest this version writes" in result.err
    assert "SpeedLimiting.fcl exists and this build did not write it" in result.err
    assert (out / "rules" / "SpeedLimiting.fcl").read_text(encoding="utf-8") == "edited"
