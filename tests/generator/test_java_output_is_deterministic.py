"""The ``java`` target writes the same bytes for the same model: twice in one process, and from
another working directory (headers name the model file by its base name)."""

from __future__ import annotations

import shutil
from pathlib import Path

from acordcs.generator.targets import targets
from tests.support.generator import build, context, snapshot
from tests.support.toolchain import SMARTROOM


def test_same_descriptor_same_files(tmp_path: Path, weblab):
    runs = []
    for n in range(2):
        (tmp_path / str(n)).mkdir()
        made = context(weblab, tmp_path / str(n), target="java", source="weblab.xmi")
        targets()["java"].run(made)
        runs.append([(f.path, f.data, f.ids, f.once) for f in made.files])
    assert runs[0] == runs[1]


def test_same_model_same_bytes_from_another_directory(tmp_path: Path, monkeypatch):
    (tmp_path / "a").mkdir()
    (tmp_path / "b" / "deep").mkdir(parents=True)
    build(SMARTROOM, tmp_path / "a" / "out", "-t", "java")
    shutil.copy(SMARTROOM, tmp_path / "b" / "deep" / "smartroom.xmi")
    monkeypatch.chdir(tmp_path / "b" / "deep")
    build(Path("smartroom.xmi"), tmp_path / "b" / "out", "-t", "java")
    a, b = snapshot(tmp_path / "a" / "out"), snapshot(tmp_path / "b" / "out")
    assert {p: d for p, (d, _) in a.items()} == {p: d for p, (d, _) in b.items()}
    assert len(a) == 3 + 2 * 3 + 1  # the API, 3 components, the manifest
