"""The documentation site: it builds with ``mkdocs build --strict``, its navigation holds every
page, and every ``$ acordcs-gen ...`` transcript in the README and the pages prints what it shows."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.toolchain import ROOT, WEBLAB, run_main

DOCS = ROOT / "docs"
TRANSCRIPTS = [
    ROOT / "README.md",
    DOCS / "getting-started.md",
    DOCS / "cli.md",
    DOCS / "diagnostics.md",
]
NOTATION = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.0" xmlns:xmi="http://www.omg.org/XMI" xmlns:notation="http://www.eclipse.org/gmf/runtime/1.0.2/notation" xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML">
  <notation:Diagram xmi:id="_d" type="PapyrusUMLClassDiagram" name="Main"/>
</xmi:XMI>
"""


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def _example_files(folder: Path) -> None:
    """The files the pages' examples name, made from the samples as the pages say."""
    (folder / "samples").symlink_to(ROOT / "samples")
    weblab = WEBLAB.read_text(encoding="utf-8")
    rule = "smallNarrow: if cycleRate is small and angle is narrow"
    broken = weblab.replace(rule, "smallNarrow: if cycleRat is small and angle is narow")
    (folder / "broken-weblab.xmi").write_text(broken, encoding="utf-8")
    typos = _edit(
        weblab,
        '<ACORDCS:CtxPolicy xmi:id="BOUML_STELT_0x20302_4"',
        '<ACORDCS:CtxPolcy xmi:id="BOUML_STELT_0x20302_4"',
    )
    typos = _edit(typos, 'trigger="periodic" frequency="0.5"', 'triger="periodic" frequency="0.5"')
    typos = _edit(typos, 'engine="fuzzy" semantics', 'engine="fuzy" semantics')
    typos = _edit(typos, 'CtxPolicySet:engine" value="fuzzy"', 'CtxPolicySet:engine" value="fuzy"')
    (folder / "typos.xmi").write_text(typos, encoding="utf-8")
    papyrus = (ROOT / "samples" / "papyrus" / "thermostat.uml").read_text(encoding="utf-8")
    bare = papyrus.split("  <ACORDCS:CtxContainer", 1)[0] + "</xmi:XMI>\n"
    (folder / "bare.uml").write_text(bare, encoding="utf-8")
    (folder / "thermostat.notation").write_text(NOTATION, encoding="utf-8")
    from tests.xmi import test_skipped_elements_are_named as skipped  # R201, R211's examples

    (folder / "events.xmi").write_text(skipped.BOUML_EVENTS, encoding="utf-8")
    (folder / "actions.xmi").write_text(skipped.ARGO_ACTIONS, encoding="utf-8")
    (folder / "lanes.xmi").write_text(skipped.VP_OWN_TYPES, encoding="utf-8")
    (folder / "diagram.xmi").write_bytes(skipped.EA_DIAGRAM_ELEMENTS.encode("cp1252"))
    (folder / "lamp.xmi").write_text(skipped.MISSPELT_CLASS, encoding="utf-8")


def test_the_site_builds_strict(tmp_path):
    try:
        import material  # noqa: F401
        import mkdocs  # noqa: F401
    except ImportError:
        if os.environ.get("CI") == "true":
            pytest.fail("mkdocs and mkdocs-material are in the dev extra: CI must have them")
        pytest.skip("mkdocs or mkdocs-material not installed (pip install -e '.[dev]')")
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(tmp_path / "site")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert (tmp_path / "site" / "diagnostics" / "index.html").is_file()


def test_the_navigation_holds_every_page():
    config = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    in_nav = set(re.findall(r"^  - [^:]+: (\S+\.md)$", config, flags=re.M))
    assert in_nav == {p.name for p in DOCS.glob("*.md")}


def _transcripts(page: Path) -> list[tuple[str, list[str], int | None]]:
    """(command, expected lines, expected exit code or None) for every `$ acordcs-gen` line."""
    found = []
    for block in re.findall(r"^```\n(.*?)^```", page.read_text(encoding="utf-8"), re.M | re.S):
        lines = block.splitlines()
        for n, line in enumerate(lines):
            if not line.startswith("$ acordcs-gen "):
                continue
            expected = []
            code = None
            for after in lines[n + 1 :]:
                if after.startswith("$ echo $?"):
                    code = int(lines[lines.index(after) + 1])
                    break
                if after.startswith("$ "):
                    break
                expected.append(after)
            found.append((line[2:], expected, code))
    return found


@pytest.mark.parametrize("page", TRANSCRIPTS, ids=lambda p: p.name)
def test_every_transcript_prints_what_it_shows(page, tmp_path, monkeypatch):
    _example_files(tmp_path)
    monkeypatch.chdir(tmp_path)
    transcripts = _transcripts(page)
    assert transcripts, f"{page.name} shows no acordcs-gen transcript"
    for command, expected, code in transcripts:
        result = run_main(shlex.split(command)[1:])
        assert result.out.splitlines() == expected, command
        if code is not None:
            assert result.code == code, command
