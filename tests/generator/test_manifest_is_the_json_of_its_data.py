"""The manifest's bytes are ``json.dumps(data, indent=1, sort_keys=True, ensure_ascii=False)`` of
its data, character for character (the manifest writes them itself, faster), for any strings its
fields may hold, and they read back to the same manifest."""

from __future__ import annotations

import json
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.generator.headers import GENERATOR
from acordcs.generator.manifest import FORMAT, Entry, Manifest, read_manifest
from acordcs.generator.paths import MANIFEST
from tests.support.generator import build
from tests.support.toolchain import WEBLAB

TEXT = st.text(st.characters(blacklist_categories=("Cs",)), max_size=12)  # UTF-8 encodable
SHA = st.text("0123456789abcdef", min_size=64, max_size=64)
ENTRY = st.builds(
    Entry,
    sha256=SHA,
    target=TEXT,
    element=TEXT,
    ids=st.lists(TEXT, max_size=3).map(tuple),
    user=st.booleans(),
    outside=st.one_of(st.just(""), SHA),
)
MANIFESTS = st.builds(
    Manifest,
    model=TEXT,
    model_sha256=TEXT,
    targets=st.dictionaries(TEXT, st.dictionaries(TEXT, TEXT, max_size=2), max_size=3),
    files=st.dictionaries(TEXT, ENTRY, max_size=6),
)


def _oracle(m: Manifest) -> bytes:
    data = {
        "format": FORMAT,
        "generator": GENERATOR,
        "model": {"file": m.model, "sha256": m.model_sha256},
        "targets": m.targets,
        "files": {
            path: {
                "sha256": e.sha256,
                "target": e.target,
                "element": e.element,
                "ids": list(e.ids),
                **({"user": True} if e.user else {}),
                **({"outside_sha256": e.outside} if e.outside else {}),
            }
            for path, e in m.files.items()
        },
    }
    return (json.dumps(data, indent=1, sort_keys=True, ensure_ascii=False) + "\n").encode()


@settings(max_examples=300, deadline=None)
@given(MANIFESTS)
def test_bytes_are_the_json_modules(m: Manifest):
    assert m.to_bytes() == _oracle(m)


def test_a_builds_manifest_reads_back_and_writes_the_same_bytes(tmp_path: Path):
    assert build(WEBLAB, tmp_path).code == 0
    written = (tmp_path / MANIFEST).read_bytes()
    m = read_manifest(tmp_path)
    assert m is not None
    assert m.to_bytes() == written == _oracle(m)
