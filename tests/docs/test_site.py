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

from tests.support.toolchain import ROOT, run_main

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
    papyrus = (ROOT / "samples" / "papyrus" / "thermostat.uml").read_text(encoding="utf-8")
    bare = papyrus.split("  <ACORDCS:CtxContainer", 1)[0] + "</xmi:XMI>\n"
    (folder / "bare.uml").write_text(bare, encoding="utf-8")
    profile = ROOT / "samples" / "papyrus" / "ACORDCS.profile.uml"
    (folder / "ACORDCS.profile.uml").write_text(
        profile.read_text(encoding="utf-8"), encoding="utf-8"
    )
    (folder / "thermostat.notation").write_text(NOTATION, encoding="utf-8")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site, built once with ``mkdocs build --strict`` (a broken link fails it)."""
    try:
        import material  # noqa: F401
        import mkdocs  # noqa: F401
    except ImportError:
        if os.environ.get("CI") == "true":
            pytest.fail("mkdocs and mkdocs-material are in the dev extra: CI must have them")
        pytest.skip("mkdocs or mkdocs-material not installed (pip install -e '.[dev]')")
    built = tmp_path_factory.mktemp("docs") / "site"
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(built)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return built


def test_the_site_builds_strict_with_a_file_per_page(site: Path):
    assert (site / "index.html").is_file()
    assert (site / "diagnostics.html").is_file() and not (site / "diagnostics").exists()


def test_the_site_opens_from_disk_and_its_links_lead_to_pages(site: Path):
    """Opened from ``file://`` in Chromium, as the README says: each link followed reaches a page
    (its own title), not a directory listing; a diagnostic code's link reaches its section."""
    from tests.support.browser import headless_chromium

    with headless_chromium() as browser:
        browser.get((site / "index.html").as_uri())
        assert "acordcs" in browser.title
        for label, expected in (
            ("Getting started", "Getting started"),
            ("Command line", "command line"),
            ("Diagnostic codes", "Diagnostic codes"),
        ):
            browser.get((site / "index.html").as_uri())
            link = next(
                a
                for a in browser.find_elements("css selector", "nav a")
                if a.get_attribute("textContent").strip() == label
            )
            browser.get(link.get_attribute("href"))  # the href a click follows
            assert browser.current_url.startswith("file://") and browser.current_url.endswith(
                ".html"
            )
            heading = browser.find_element("css selector", "article h1").text
            assert expected.lower() in heading.lower(), (label, heading)
            assert "Index of" not in browser.page_source
        browser.get((site / "diagnostics.html").as_uri() + "#l402")
        section = browser.find_element("id", "l402")
        assert section.text.startswith("L402 rule variable is not an attribute")
        toc = browser.find_elements("css selector", ".md-nav--secondary a")
        shown = {a.get_attribute("textContent").strip() for a in toc}
        assert any(t.startswith("L402 rule variable") for t in shown), sorted(shown)[:5]


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
