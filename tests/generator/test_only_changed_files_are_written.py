"""A build writes only files whose bytes change (the others keep their mtime), a rebuild of the
same model writes nothing at all, and the same model gives the same bytes wherever and however
it is built."""

from __future__ import annotations

import json
import os
from pathlib import Path

from tests.support.generator import FASTER, build, snapshot, weblab_variant
from tests.support.toolchain import WEBLAB

COMPONENTS = ["Access", "Locomotion", "Navigator", "PanoramicCamera", "Recovery", "Vision"]
MONITORS = ["Control", "Telemetry", "Usage"]
PACKAGE = sorted(
    [
        "weblab_app/UserSide.py",
        "weblab_app/WebLabSide.py",
        "weblab_app/__init__.py",
        "weblab_app/base/__init__.py",
        "weblab_app/components/__init__.py",
        "weblab_app/descriptor.xml",
        "weblab_app/registry.py",
        "weblab_app/model_types.py",
        "weblab_app/monitors/__init__.py",
        *(f"weblab_app/{d}/{c}.py" for d in ("base", "components") for c in COMPONENTS),
        *(f"weblab_app/{d}/{m}.py" for d in ("base", "monitors") for m in MONITORS),
    ]
)
JAVA = [
    *(f"java/org/acordcs/runtime/{name}.java" for name in ("CtxComponent", "Port", "RuleEngine")),
    *(
        f"java/weblab/{component}{suffix}.java"
        for component in (
            "Access",
            "Locomotion",
            "Navigator",
            "PanoramicCamera",
            "Recovery",
            "Vision",
        )
        for suffix in ("", "Base")
    ),
]
SHELL = [
    "bin/env.sh",
    "bin/start-all",
    "bin/start-host",
    "bin/stop-all",
    "bin/stop-host",
    "bin/console",
    *(
        f"bin/{c}-{verb}"
        for c in ("UserSide", "WebLabSide")
        for verb in ("start", "status", "stop")
    ),
]
FILES = sorted(
    [
        ".acordcs-manifest.json",
        "WebLab.descriptor.xml",
        "acordcs-descriptor.xsd",
        "rules/BandwidthLimiting.fcl",
        "rules/Recovering.clp",
        "rules/SpeedLimiting.fcl",
        *JAVA,
        *PACKAGE,
        *SHELL,
    ]
)


def test_first_build_writes_every_file(tmp_path: Path):
    result = build(WEBLAB, tmp_path / "out")
    assert result.code == 0, result.both
    assert sorted(snapshot(tmp_path / "out")) == FILES
    assert (
        "59 written, 0 deleted, 0 unchanged (targets: config, java, python, rules, shell)"
        in result.out
    )


def test_rebuild_of_the_same_model_writes_nothing(tmp_path: Path):
    build(WEBLAB, tmp_path)
    before = snapshot(tmp_path)
    result = build(WEBLAB, tmp_path)
    assert result.code == 0
    assert (
        result.out
        == f"{tmp_path}: up to date (config, java, python, rules, shell; model unchanged, nothing written)\n"
    )
    assert snapshot(tmp_path) == before  # bytes and mtime_ns


def test_forced_rebuild_runs_the_targets_and_writes_nothing(tmp_path: Path):
    build(WEBLAB, tmp_path)
    before = snapshot(tmp_path)
    result = build(WEBLAB, tmp_path, "--force")
    assert result.code == 0
    assert "nothing changed (59 files up to date)" in result.out
    assert snapshot(tmp_path) == before


def test_a_changed_rule_rewrites_only_the_files_holding_it(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    before = snapshot(out)
    changed = weblab_variant(tmp_path, FASTER)
    result = build(changed, out)
    assert result.code == 0, result.both
    after = snapshot(out)
    rewritten = {p for p in after if after[p] != before[p]}
    assert rewritten == {
        ".acordcs-manifest.json",
        "WebLab.descriptor.xml",  # it holds the rules too
        "rules/SpeedLimiting.fcl",
        "weblab_app/descriptor.xml",  # the package's copy of the descriptor
    }
    assert (
        "RULE largeNarrow : IF Control_cycleRate IS large AND Control_angle IS narrow THEN Locomotion_maxSpeed IS medium;"
        in after["rules/SpeedLimiting.fcl"][0].decode()
    )
    assert result.out.splitlines()[:2] == [
        f"wrote {out}/WebLab.descriptor.xml",
        f"wrote {out}/rules/SpeedLimiting.fcl",
    ]


def test_a_deleted_or_edited_generated_file_is_restored(tmp_path: Path):
    build(WEBLAB, tmp_path)
    original = snapshot(tmp_path)
    (tmp_path / "rules" / "Recovering.clp").unlink()
    (tmp_path / "rules" / "SpeedLimiting.fcl").write_text("edited", encoding="utf-8")
    result = build(WEBLAB, tmp_path)
    assert result.code == 0
    restored = {p: d for p, (d, _) in snapshot(tmp_path).items()}
    # the edit is not lost: saved beside the file before it was regenerated (tests/generator/
    # test_edited_generated_files_are_saved.py has the rest)
    assert restored.pop("rules/SpeedLimiting.fcl.edited") == b"edited"
    assert restored == {p: d for p, (d, _) in original.items()}
    assert "3 written, 0 deleted, 57 unchanged" in result.out


def test_same_model_same_bytes_wherever_it_is_built_from(tmp_path: Path, monkeypatch):
    build(WEBLAB, tmp_path / "a")
    copy = tmp_path / "elsewhere" / "weblab.xmi"
    copy.parent.mkdir()
    copy.write_bytes(WEBLAB.read_bytes())
    monkeypatch.chdir(copy.parent)
    build(Path("weblab.xmi"), tmp_path / "b")
    a, b = snapshot(tmp_path / "a"), snapshot(tmp_path / "b")
    assert {p: d for p, (d, _) in a.items()} == {p: d for p, (d, _) in b.items()}


def test_manifest_traces_each_file_to_model_elements(tmp_path: Path, weblab):
    build(WEBLAB, tmp_path)
    manifest = json.loads((tmp_path / ".acordcs-manifest.json").read_text(encoding="utf-8"))
    assert manifest["model"]["file"] == "weblab.xmi"
    assert set(manifest["targets"]) == {"config", "java", "python", "rules", "shell"}
    files = manifest["files"]
    assert sorted(files) == [f for f in FILES if f != ".acordcs-manifest.json"]
    speed = next(ps for ps in weblab.policy_sets if ps.name == "SpeedLimiting")
    entry = files["rules/SpeedLimiting.fcl"]
    assert entry["target"] == "rules" and entry["element"] == speed.qualified_name
    assert entry["ids"][0] == speed.id and {p.id for p in speed.policies} <= set(entry["ids"])
    import hashlib

    for rel, entry in files.items():
        user_java = rel.startswith("java/weblab/") and not rel.endswith("Base.java")
        user_python = rel.startswith(("weblab_app/components/", "weblab_app/monitors/"))
        assert entry.get("user", False) == (user_python or user_java)
        assert entry["sha256"] == hashlib.sha256((tmp_path / rel).read_bytes()).hexdigest()
    assert os.path.getsize(tmp_path / ".acordcs-manifest.json") > 0


def test_the_same_model_under_another_name_is_built_again(tmp_path: Path):
    out = tmp_path / "out"
    build(WEBLAB, out)
    renamed = tmp_path / "lab.xmi"
    renamed.write_bytes(WEBLAB.read_bytes())
    result = build(renamed, out)
    assert result.code == 0
    # every header names the model file; the user's files (written once) are not written again
    assert "42 written, 0 deleted, 17 unchanged" in result.out
    assert "in model file lab.xmi." in (out / "rules" / "Recovering.clp").read_text(
        encoding="utf-8"
    )
