"""``build --check`` regenerates in memory and compares the bytes with the files on disk: the
manifest only says which files are generated. A generated file tampered with (its sha256 in the
manifest updated to match), or deleted together with its entry, is found; a manifest that cannot
be read makes it exit 1. What is the user's (files written once, lines in protected regions) is not
compared."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from acordcs.generator.paths import MANIFEST
from tests.support.generator import build, snapshot
from tests.support.toolchain import WEBLAB

FCL = "rules/SpeedLimiting.fcl"


def _manifest(out: Path) -> dict:
    return json.loads((out / MANIFEST).read_text(encoding="utf-8"))


def _save(out: Path, manifest: dict) -> None:
    (out / MANIFEST).write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n", "utf-8")


def test_a_tampered_file_with_a_matching_manifest_entry_fails_the_check(tmp_path: Path):
    build(WEBLAB, tmp_path)
    tampered = (tmp_path / FCL).read_bytes() + b"(* mine *)\n"
    (tmp_path / FCL).write_bytes(tampered)
    manifest = _manifest(tmp_path)
    manifest["files"][FCL]["sha256"] = hashlib.sha256(tampered).hexdigest()
    _save(tmp_path, manifest)
    before = snapshot(tmp_path)
    result = build(WEBLAB, tmp_path, "--check")
    assert result.code == 1, result.both
    assert f"{tmp_path}: not up to date: 1 file to write, 0 to delete" in result.err
    assert snapshot(tmp_path) == before


def test_a_file_deleted_with_its_entry_fails_the_check(tmp_path: Path):
    build(WEBLAB, tmp_path)
    (tmp_path / FCL).unlink()
    manifest = _manifest(tmp_path)
    del manifest["files"][FCL]
    _save(tmp_path, manifest)
    result = build(WEBLAB, tmp_path, "--check")
    assert result.code == 1, result.both
    assert "not up to date: 1 file to write" in result.err


def test_a_corrupted_manifest_fails_the_check(tmp_path: Path):
    build(WEBLAB, tmp_path)
    for corrupted in ("{not json", '{"format": 1, "files": [], "targets": {}}', ""):
        (tmp_path / MANIFEST).write_text(corrupted, encoding="utf-8")
        result = build(WEBLAB, tmp_path, "--check")
        assert result.code == 1, (corrupted, result.both)
        assert f"{tmp_path}/{MANIFEST} cannot be used: " in result.err
    build(WEBLAB, tmp_path / "again")
    manifest = _manifest(tmp_path / "again")
    manifest["files"][FCL]["sha256"] = "not a sha"
    _save(tmp_path / "again", manifest)
    result = build(WEBLAB, tmp_path / "again", "--check")
    assert result.code == 1 and "is not a sha256" in result.err


def test_what_is_the_users_does_not_fail_the_check(tmp_path: Path):
    build(WEBLAB, tmp_path)
    assert build(WEBLAB, tmp_path, "--check").code == 0
    user = tmp_path / "weblab_app" / "components" / "Locomotion.py"
    user.write_text(user.read_text(encoding="utf-8") + "# mine\n", encoding="utf-8")
    env = tmp_path / "bin" / "env.sh"
    text = env.read_text(encoding="utf-8")
    begin = next(line for line in text.splitlines() if line.startswith("# BEGIN USER "))
    env.write_text(text.replace(begin + "\n", begin + "\nexport MINE=1\n", 1), encoding="utf-8")
    result = build(WEBLAB, tmp_path, "--check")
    assert result.code == 0, result.both
    assert f"{tmp_path}: up to date" in result.out
