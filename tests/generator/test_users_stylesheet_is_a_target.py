"""``acordcs-gen build MODEL -o DIR -t path/to/mine.xsl`` runs the user's XSLT 3.0 stylesheet over
the descriptor as a built-in target runs: its files in the manifest under the file's name, checked
paths, all or nothing, up to date when nothing changed. Every result document is a file, listed or
not; a listing, when the principal result is one, adds each file's provenance and flags; a listing
naming a file not written, or a principal result neither empty nor a listing, fails the target.
The complete example of docs/build.md (a systemd unit per container, with no listing) writes what
the page shows, and systemd itself accepts the units."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from acordcs.generator.paths import MANIFEST
from tests.support.generator import build, snapshot
from tests.support.toolchain import ROOT, WEBLAB, no_crash, run_main

PAGE = (ROOT / "docs" / "build.md").read_text(encoding="utf-8")
SECTION = PAGE.split("## Your own stylesheet as a target\n", 1)[1].split("\n## ", 1)[0]


def _stylesheet() -> str:
    (xml,) = re.findall(r"^```xml\n(.*?)^```$", SECTION, flags=re.S | re.M)
    return xml


def _transcript() -> list[tuple[str, list[str]]]:
    (block,) = re.findall(r"^```\n(\$ .*?)^```$", SECTION, flags=re.S | re.M)
    out = []
    for chunk in block.split("$ ")[1:]:
        command, *lines = chunk.rstrip("\n").split("\n")
        out.append((command, lines))
    return out


@pytest.fixture
def project(tmp_path: Path, monkeypatch) -> Path:
    (tmp_path / "samples" / "weblab").mkdir(parents=True)
    shutil.copyfile(WEBLAB, tmp_path / "samples" / "weblab" / "weblab.xmi")
    (tmp_path / "systemd.xsl").write_text(_stylesheet(), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_the_pages_example_writes_what_the_page_shows(project: Path):
    assert "<files" not in _stylesheet()  # it needs no listing
    (build_command, said), (cat_command, unit) = _transcript()
    assert build_command.startswith("acordcs-gen build ") and cat_command.startswith("cat ")
    result = run_main(build_command.split()[1:])
    assert result.code == 0, result.both
    assert result.out.splitlines() == said
    assert Path(cat_command.split()[1]).read_text(encoding="utf-8").splitlines() == unit
    manifest = json.loads((project / "build" / "units" / MANIFEST).read_text(encoding="utf-8"))
    assert set(manifest["targets"]) == {"systemd.xsl"}
    assert {e["target"] for e in manifest["files"].values()} == {"systemd.xsl"}
    again = run_main(build_command.split()[1:])
    assert "up to date (systemd.xsl; model unchanged, nothing written)" in again.out


def test_systemd_accepts_the_units(project: Path):
    analyze = shutil.which("systemd-analyze")
    if analyze is None:
        reason = "systemd-analyze is not on PATH (it comes with systemd)"
        if os.environ.get("CI") == "true":
            pytest.fail(f"the systemd test cannot run in CI: {reason}")
        pytest.skip(reason)
    assert build(WEBLAB, project / "out", "-t", "systemd.xsl").code == 0
    units = sorted((project / "out" / "systemd").glob("*.service"))
    assert [u.name for u in units] == [
        "weblab_app-UserSide.service",
        "weblab_app-WebLabSide.service",
    ]
    done = subprocess.run(
        [analyze, "verify", "--man=no", *map(str, units)],
        cwd=project / "out" / "systemd",
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 0 and not done.stdout + done.stderr, done.stdout + done.stderr


def test_with_other_targets_one_manifest_and_an_edit_rebuilds(project: Path):
    out = project / "out"
    assert build(WEBLAB, out, "-t", "python,systemd.xsl").code == 0
    manifest = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
    assert set(manifest["targets"]) == {"python", "systemd.xsl"}
    stylesheet = project / "systemd.xsl"
    stylesheet.write_text(
        stylesheet.read_text(encoding="utf-8").replace("Restart=on-failure", "Restart=always"),
        encoding="utf-8",
    )
    result = build(WEBLAB, out, "-t", "systemd.xsl")
    assert result.code == 0, result.both
    assert "2 written, 0 deleted" in result.out  # the units, not the python package
    assert "Restart=always" in (out / "systemd" / "weblab_app-UserSide.service").read_text()


def _mine(project: Path, body: str) -> Path:
    path = project / "mine.xsl"
    path.write_text(
        '<xsl:stylesheet version="3.0" xmlns:xsl="http://www.w3.org/1999/XSL/Transform" '
        'xmlns="http://acordcs.org/codegen/1.0"><xsl:template match="/">'
        f"{body}</xsl:template></xsl:stylesheet>",
        encoding="utf-8",
    )
    return path


@pytest.mark.parametrize(
    "href", ["../escaped.txt", "file:///tmp/acordcs-escaped.txt", "/etc/acordcs-escaped.txt"]
)
def test_a_result_document_outside_the_output_fails_and_writes_nothing(project: Path, href):
    out = project / "out"
    assert build(WEBLAB, out, "-t", "config").code == 0
    before = snapshot(out)
    mine = _mine(
        project,
        f'<xsl:result-document href="{href}" method="text">x</xsl:result-document>'
        '<files><file path="escaped.txt"/></files>',
    )
    result = build(WEBLAB, out, "-t", f"config,{mine}")
    no_crash(result)
    assert result.code == 1
    assert "wrote a result document outside the output directory" in result.err
    assert snapshot(out) == before
    assert not (project / "escaped.txt").exists()
    assert not Path("/tmp/acordcs-escaped.txt").exists()


def test_serialization_attributes_are_the_stylesheets(project: Path):
    mine = _mine(
        project,
        '<xsl:result-document href="a.xml" method="xml" indent="yes" omit-xml-declaration="yes">'
        '<a xmlns=""><b/></a></xsl:result-document>'
        '<xsl:result-document href="b.txt" method="text" encoding="US-ASCII">plain &amp; '
        "text</xsl:result-document>"
        '<xsl:result-document href="c 1;2.txt" method="text">&#x1F600;:9:&#10;'
        "</xsl:result-document>"
        '<files><file path="a.xml"/><file path="b.txt"/><file path="c 1;2.txt"/></files>',
    )
    assert build(WEBLAB, project / "out", "-t", str(mine)).code == 0
    assert (project / "out" / "a.xml").read_text() == "<a>\n   <b/>\n</a>\n"
    assert (project / "out" / "b.txt").read_bytes() == b"plain & text"
    assert (project / "out" / "c 1;2.txt").read_text(encoding="utf-8") == "\U0001f600:9:\n"
    ascii_only = _mine(
        project,
        '<xsl:result-document href="c.txt" method="text" encoding="US-ASCII">caf&#233;'
        '</xsl:result-document><files><file path="c.txt"/></files>',
    )
    result = build(WEBLAB, project / "out2", "-t", str(ascii_only))
    assert result.code == 1 and "SERE0008" in result.err
    assert not (project / "out2").exists()


def test_a_missing_stylesheet_is_a_usage_error(project: Path):
    result = build(WEBLAB, project / "out", "-t", "nowhere/mine.xsl")
    assert result.code == 2
    assert "stylesheet 'nowhere/mine.xsl' not found" in result.err
    assert not (project / "out").exists()


def test_list_is_unchanged_by_a_stylesheet_path(project: Path):
    listed = run_main(["build", "--list"])
    assert "systemd.xsl" not in listed.out


def test_a_listing_says_once_regions_and_executable(project: Path):
    out = project / "out"
    mine = _mine(
        project,
        '<xsl:result-document href="run.sh" method="text">#!/bin/sh&#10;exit 0&#10;'
        '</xsl:result-document><xsl:result-document href="env.sh" method="text">X=1&#10;'
        "# BEGIN USER k&#10;# END USER k&#10;</xsl:result-document>"
        '<xsl:result-document href="yours.txt" method="text">fill me&#10;</xsl:result-document>'
        '<files><file path="run.sh" executable="yes"/><file path="env.sh" regions="hash"/>'
        '<file path="yours.txt" once="yes"/></files>',
    )
    assert build(WEBLAB, out, "-t", str(mine)).code == 0
    assert os.access(out / "run.sh", os.X_OK) and not os.access(out / "env.sh", os.X_OK)
    (out / "env.sh").write_text("X=1\n# BEGIN USER k\nMINE=2\n# END USER k\n", encoding="utf-8")
    (out / "yours.txt").write_text("filled\n", encoding="utf-8")
    assert build(WEBLAB, out, "-t", str(mine), "--force").code == 0
    assert "MINE=2" in (out / "env.sh").read_text(encoding="utf-8")
    assert (out / "yours.txt").read_text(encoding="utf-8") == "filled\n"
    manifest = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
    assert manifest["files"]["yours.txt"]["user"] is True
    assert "outside_sha256" in manifest["files"]["env.sh"]

    wrong = _mine(
        project,
        '<xsl:result-document href="a.txt" method="text">a</xsl:result-document>'
        '<files><file path="a.txt" regions="semicolon"/></files>',
    )
    result = build(WEBLAB, project / "out2", "-t", str(wrong))
    assert (
        result.code == 1 and "regions='semicolon', not a syntax of protected regions" in result.err
    )


def test_files_need_no_listing_and_a_listing_adds_their_provenance(project: Path):
    out = project / "out"
    mine = _mine(
        project,
        '<xsl:result-document href="a/unlisted.txt" method="text">a</xsl:result-document>'
        '<xsl:result-document href="b.txt" method="text">b</xsl:result-document>'
        '<files><file path="b.txt" element="WebLab" ids="i1 i2"/></files>',
    )
    result = build(WEBLAB, out, "-t", str(mine))
    assert result.code == 0, result.both
    assert (out / "a" / "unlisted.txt").read_text() == "a" and (out / "b.txt").read_text() == "b"
    files = json.loads((out / MANIFEST).read_text(encoding="utf-8"))["files"]
    assert files["a/unlisted.txt"]["element"] == "" and files["a/unlisted.txt"]["ids"] == []
    assert files["b.txt"]["element"] == "WebLab" and files["b.txt"]["ids"] == ["i1", "i2"]
    assert {e["target"] for e in files.values()} == {"mine.xsl"}
    # An unlisted file is the build's like any other: deleted when no longer written.
    _mine(project, '<xsl:result-document href="b.txt" method="text">b</xsl:result-document>')
    result = build(WEBLAB, out, "-t", str(mine))
    assert result.code == 0, result.both
    assert not (out / "a" / "unlisted.txt").exists() and (out / "b.txt").exists()


@pytest.mark.parametrize(
    ("principal", "said"),
    [
        ("hello", "it holds text, 'hello'"),
        ("<other/>", "it is <other>, in namespace 'http://acordcs.org/codegen/1.0'"),
        ('<files xmlns=""/>', "it is <files>, in no namespace"),
    ],
)
def test_a_principal_result_neither_empty_nor_a_listing_fails(project: Path, principal, said):
    mine = _mine(
        project,
        f'<xsl:result-document href="a.txt" method="text">a</xsl:result-document>{principal}',
    )
    result = build(WEBLAB, project / "out", "-t", str(mine))
    no_crash(result)
    assert result.code == 1
    assert (
        "target mine.xsl: the stylesheet's principal result is neither empty nor a file listing: "
        + said
    ) in result.err
    assert "leave the principal result empty" in result.err
    assert not (project / "out").exists()


def test_a_listing_naming_a_file_not_written_fails(project: Path):
    mine = _mine(
        project,
        '<xsl:result-document href="a.txt" method="text">a</xsl:result-document>'
        '<files><file path="a.txt"/><file path="b.txt"/></files>',
    )
    result = build(WEBLAB, project / "out", "-t", str(mine))
    no_crash(result)
    assert result.code == 1
    assert "the stylesheet lists 'b.txt' but did not write it (it wrote: 'a.txt')" in result.err
    assert not (project / "out").exists()
