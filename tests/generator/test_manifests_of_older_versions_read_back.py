"""A manifest written by an older acordcs reads back as what it recorded, and one of another
format, or not a manifest at all, is refused in words (``ManifestError``), never half-trusted.

Format 1 is the only one there has been; its writers differed in what an entry holds: the first
(acordcs.codegen, 0ea7ee6) wrote ``sha256``, ``target``, ``element`` and ``ids`` only; the next
(5e2546d) added ``"user": true`` for a user's file; the current one adds ``outside_sha256`` for a
file with protected regions. Each is written here as those versions wrote it (``json.dumps(...,
indent=1, sort_keys=True, ensure_ascii=False)``, by hand so that no code of today makes it)."""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path

import pytest

from acordcs.generator.manifest import FORMAT, Entry, Manifest, ManifestError, read_manifest
from acordcs.generator.paths import MANIFEST

A = "a" * 64
B = "b" * 64
C = "0123456789abcdef" * 4

FIRST = (
    """{
 "files": {
  "bin/env.sh": {
   "element": "",
   "ids": [],
   "sha256": "<A>",
   "target": "shell"
  },
  "config/weblab.xml": {
   "element": "WebLab",
   "ids": [
    "EAID_1",
    "EAID_2"
   ],
   "sha256": "<B>",
   "target": "config"
  }
 },
 "format": 1,
 "generator": "acordcs-gen 0.0.1",
 "model": {
  "file": "weblab.xmi",
  "sha256": "<C>"
 },
 "targets": {
  "config": {
   "fingerprint": "f1",
   "model_sha256": "<C>"
  }
 }
}
""".replace("<A>", A)
    .replace("<B>", B)
    .replace("<C>", C)
)

SECOND = """{
 "files": {
  "app/Robot.py": {
   "element": "Robot",
   "ids": [
    "id7"
   ],
   "sha256": "<A>",
   "target": "python",
   "user": true
  }
 },
 "format": 1,
 "generator": "acordcs-gen 0.0.2",
 "model": {
  "file": "m.xmi",
  "sha256": "<C>"
 },
 "targets": {}
}
""".replace("<A>", A).replace("<C>", C)


def _write(tmp_path: Path, text: str | bytes) -> Path:
    data = text.encode() if isinstance(text, str) else text
    (tmp_path / MANIFEST).write_bytes(data)
    return tmp_path


def test_the_first_versions_manifest_reads_back_with_no_user_file_and_no_regions(tmp_path):
    m = read_manifest(_write(tmp_path, FIRST))
    assert m == Manifest(
        "weblab.xmi",
        C,
        {"config": {"fingerprint": "f1", "model_sha256": C}},
        {
            "bin/env.sh": Entry(A, "shell", "", (), False, ""),
            "config/weblab.xml": Entry(B, "config", "WebLab", ("EAID_1", "EAID_2"), False, ""),
        },
    )
    # written again it is that version's text, but for the generator that writes it
    written = json.loads(m.to_bytes())
    assert written["generator"] != "acordcs-gen 0.0.1"
    assert {**written, "generator": "acordcs-gen 0.0.1"} == json.loads(FIRST)


def test_the_second_versions_user_file_stays_the_users(tmp_path):
    m = read_manifest(_write(tmp_path, SECOND))
    assert m is not None
    assert m.files == {"app/Robot.py": Entry(A, "python", "Robot", ("id7",), True, "")}
    assert (m.model, m.model_sha256, m.targets) == ("m.xmi", C, {})
    assert json.loads(m.to_bytes())["files"] == json.loads(SECOND)["files"]


def test_the_current_versions_regions_digest_reads_back(tmp_path):
    current = Manifest("m.xmi", C, {}, {"bin/env.sh": Entry(A, "shell", outside=B)})
    m = read_manifest(_write(tmp_path, current.to_bytes()))
    assert m == current and m.files["bin/env.sh"].outside == B


def test_an_entry_without_element_or_ids_and_a_manifest_without_a_model_read_as_empty(tmp_path):
    text = json.dumps(
        {"format": 1, "files": {"x.txt": {"sha256": A, "target": "t"}}, "targets": {}}
    )
    assert read_manifest(_write(tmp_path, text)) == Manifest(
        "", "", {}, {"x.txt": Entry(A, "t", "", (), False, "")}
    )


def test_only_json_true_makes_a_file_the_users(tmp_path):
    for value in ("true", 1, "yes"):
        entry = {"sha256": A, "target": "t", "user": value}
        text = json.dumps({"format": 1, "files": {"x.txt": entry}, "targets": {}})
        m = read_manifest(_write(tmp_path, text))
        assert m is not None and m.files["x.txt"].user is False, value


def test_an_entry_is_no_users_file_and_has_no_regions_unless_it_says_so():
    entry = Entry(A, "t")
    assert (entry.element, entry.ids, entry.user, entry.outside) == ("", (), False, "")
    written = json.loads(Manifest(files={"x.txt": entry}).to_bytes())["files"]["x.txt"]
    assert written == {"element": "", "ids": [], "sha256": A, "target": "t"}
    with pytest.raises(dataclasses.FrozenInstanceError):
        entry.user = True  # type: ignore[misc]  # a record of what a build wrote


def test_no_manifest_is_none(tmp_path):
    assert read_manifest(tmp_path) is None


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"format": 2, "files": {}, "targets": {}}, f"format 2, not {FORMAT}"),
        ({"format": 0, "files": {}, "targets": {}}, f"format 0, not {FORMAT}"),
        ({"format": "1", "files": {}, "targets": {}}, f"format '1', not {FORMAT}"),
        ({"files": {}, "targets": {}}, f"format None, not {FORMAT}"),
        ({"format": 1, "targets": {}}, "it is not a manifest this version writes ('files')"),
        ({"format": 1, "files": {}}, "it is not a manifest this version writes ('targets')"),
        (
            {"format": 1, "files": {"x": {"target": "t"}}, "targets": {}},
            "it is not a manifest this version writes ('sha256')",
        ),
        (
            {"format": 1, "files": {"x": {"sha256": A}}, "targets": {}},
            "it is not a manifest this version writes ('target')",
        ),
        (
            {"format": 1, "files": {"x": {"sha256": A.upper(), "target": "t"}}, "targets": {}},
            "the sha256 of 'x' is not a sha256",
        ),
        (
            {"format": 1, "files": {"x": {"sha256": A + "0", "target": "t"}}, "targets": {}},
            "the sha256 of 'x' is not a sha256",
        ),
        (
            {
                "format": 1,
                "files": {"x": {"sha256": A, "target": "t", "outside_sha256": "b"}},
                "targets": {},
            },
            "the outside_sha256 of 'x' is not a sha256",
        ),
        (
            {"format": 1, "files": {"../x": {"sha256": A, "target": "t"}}, "targets": {}},
            "it lists '../x': ",
        ),
        (
            {"format": 1, "files": {MANIFEST: {"sha256": A, "target": "t"}}, "targets": {}},
            f"it lists {MANIFEST!r}: ",
        ),
    ],
)
def test_another_format_or_a_broken_manifest_is_refused_in_words(tmp_path, data, message):
    with pytest.raises(ManifestError) as info:
        read_manifest(_write(tmp_path, json.dumps(data)))
    assert str(info.value).startswith(message)


@pytest.mark.parametrize("text", ["[1, 2]", '{"format": 1, "files": [], "targets": {}}', "{"])
def test_what_is_not_a_json_object_of_the_form_is_not_a_manifest(tmp_path, text):
    with pytest.raises(ManifestError, match=r"^it is not a manifest this version writes"):
        read_manifest(_write(tmp_path, text))


def test_a_fifo_in_the_manifests_place_is_refused_unread(tmp_path):
    os.mkfifo(tmp_path / MANIFEST)
    with pytest.raises(ManifestError, match=r"^it is a named pipe \(FIFO\), not read$"):
        read_manifest(tmp_path)
