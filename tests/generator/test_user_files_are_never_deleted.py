"""A user's file (a class written once for the user to fill in) is recognised by its own header,
``Written once: yours to edit``, and never deleted, whatever the manifest says: an entry naming it
as a generated file (with its sha256), or its entry with the ``user`` flag removed, no longer makes
a build delete it."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

from acordcs.generator.headers import USER_MARK, is_users
from acordcs.generator.paths import MANIFEST
from tests.support.generator import build, weblab_variant
from tests.support.toolchain import SMARTROOM, WEBLAB

USER_FILE = "weblab_app/components/Vision.py"
RENAMED = ('name="Vision" xmi:id', 'name="Camera" xmi:id')  # the component: its user file is stale


def _manifest(out: Path) -> dict:
    return json.loads((out / MANIFEST).read_text(encoding="utf-8"))


def _save(out: Path, manifest: dict) -> None:
    (out / MANIFEST).write_text(json.dumps(manifest), encoding="utf-8")


@pytest.mark.parametrize("model", [WEBLAB, SMARTROOM], ids=["weblab", "smartroom"])
def test_every_file_written_once_says_so_in_its_header(tmp_path: Path, model: Path):
    assert build(model, tmp_path).code == 0
    entries = _manifest(tmp_path)["files"]
    users = {p for p, e in entries.items() if e.get("user")}
    assert {p.rsplit(".", 1)[1] for p in users} == {"py", "java"}  # both targets write some
    for path, entry in entries.items():
        data = (tmp_path / path).read_bytes()
        assert is_users(data) == bool(entry.get("user")), path
        if entry.get("user"):
            assert USER_MARK in data.decode("utf-8").splitlines()[1], path  # the header's line 2


def test_a_user_file_whose_user_flag_was_removed_is_not_deleted(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    manifest = _manifest(out)
    del manifest["files"][USER_FILE]["user"]
    # as if it had always been the bytes the build wrote: only the header tells it is the user's
    mine = (out / USER_FILE).read_bytes()
    _save(out, manifest)
    result = build(weblab_variant(tmp_path, RENAMED), out)
    assert result.code == 0, result.both
    assert (out / USER_FILE).read_bytes() == mine
    # a renamed component: G704 says where its code is and what to move (the code stays)
    assert f"{out}/{USER_FILE}:1:1: warning: G704 {USER_FILE} is your code for" in result.out
    assert _manifest(out)["files"][USER_FILE]["user"] is True  # recorded as the user's again


def test_a_manifest_entry_naming_a_users_file_does_not_delete_it(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    # the user's own helper, in the header style of the classes written for them
    helper = out / "weblab_app" / "components" / "helpers.py"
    text = f"# My helpers.\n# {USER_MARK}, never overwritten by a build.\nX = 1\n"
    helper.write_text(text, encoding="utf-8")
    manifest = _manifest(out)
    manifest["files"]["weblab_app/components/helpers.py"] = {
        "sha256": hashlib.sha256(text.encode()).hexdigest(),
        "target": "python",
        "element": "",
        "ids": [],
    }
    _save(out, manifest)
    result = build(WEBLAB, out, "--force")
    assert result.code == 0, result.both
    assert helper.read_text(encoding="utf-8") == text
    assert "deleted" not in result.out


def test_a_stale_generated_file_is_still_deleted(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    result = build(weblab_variant(tmp_path, RENAMED), out)
    assert f"deleted {out}/weblab_app/base/Vision.py" in result.out
    assert not (out / "weblab_app" / "base" / "Vision.py").exists()
