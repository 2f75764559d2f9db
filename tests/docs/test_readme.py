"""The README tells the truth: its codes table matches the tools (its `make demo` transcript is
checked by tests/samples/weblab/test_make_demo.py, beside the demo's other tests)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from acordcs.diagnostics import CODES
from tests.support.toolchain import ROOT

README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_readme_names_the_two_commands():
    assert "make demo" in README and "make test" in README


def test_every_diagnostic_code_is_in_the_codes_page_with_its_severity_and_meaning():
    page = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    rows = dict(re.findall(r"^\| \[([A-Z]\d{3})\]\(#[a-z]\d{3}\) \| (.+) \|$", page, flags=re.M))
    for code, (severity, title) in CODES.items():
        assert code in rows, f"{code} missing from docs/diagnostics.md's table"
        assert rows[code] == f"{severity} | {title}", f"docs/diagnostics.md row for {code} is stale"
    assert set(rows) == set(CODES), "docs/diagnostics.md lists codes that do not exist"
    # The heading says what the code means (the site's table of contents shows it) and keeps the
    # code's own anchor (#l402: SARIF's helpUri and the table link to it).
    sections = re.findall(
        r"^### ([A-Z]\d{3}) (.+) \{#([a-z]\d{3})\}\n\nSeverity: \*\*(\w+)\*\*\.\n", page, flags=re.M
    )
    assert [(c, t, a, s) for c, t, a, s in sections] == [
        (c, t, c.lower(), str(s)) for c, (s, t) in CODES.items()
    ], "one section per code, in the table's order, with its meaning, anchor and severity"


def test_runtime_assembly_example_prints_what_the_readme_shows(monkeypatch):
    monkeypatch.chdir(ROOT)
    runtime_doc = (ROOT / "docs" / "runtime.md").read_text(encoding="utf-8")
    section = runtime_doc.split("**From a model**", 1)[1]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    shown = section.split("```text\n", 1)[1].split("```", 1)[0]
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout == shown


# ------------------------------------------------------------------------------ the layout table
LAYOUT = README.split("\n## Layout\n", 1)[1].split("\n## ", 1)[0]
# The README's table is the short one; docs/layout.md names every module.
MODULES = (ROOT / "docs" / "layout.md").read_text(encoding="utf-8")
TABLES = {"README.md": LAYOUT, "docs/layout.md": MODULES}
# A backticked name is a path when it ends with "/" or with one of the repository's file kinds.
PATH_LIKE = re.compile(
    r"^[\w.*-]+(?:/[\w.*-]+)*(?:/|\.(?:py|xsl|xsd|lark|ecore|xmi|uml|txt|java|md|yml|toml|sh))$"
)


def _layout_rows(table: str) -> list[tuple[list[str], list[str]]]:
    """(paths of the first column, backticked names of the second) for each row of the table."""
    rows = []
    for line in table.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 2 or cells[0] in ("path", "---"):
            continue
        rows.append((re.findall(r"`([^`]+)`", cells[0]), re.findall(r"`([^`]+)`", cells[1])))
    return rows


def _resolve(name: str, base: Path) -> list[Path]:
    """What a name of the table stands for: a path from the repository's root, from the row's
    directory, or a name (a glob) somewhere under the row's directory."""
    for start in (ROOT, base):
        found = sorted(start.glob(name.rstrip("/")))
        if found:
            return found
    return sorted(p for p in base.rglob(name.rstrip("/")) if "__pycache__" not in p.parts)


def _named_by_the_layout(table: str) -> tuple[set[Path], list[str]]:
    named: set[Path] = set()
    missing = []
    for firsts, names in _layout_rows(table):
        first = ROOT / firsts[0]
        base = first if firsts[0].endswith("/") else first.parent
        for name in [*firsts, *(n for n in names if PATH_LIKE.match(n))]:
            found = _resolve(name, base)
            if not found:
                missing.append(f"{name} (row {firsts[0]})")
            named.update(found)
    return named, missing


@pytest.mark.parametrize("where", TABLES)
def test_every_path_in_the_layout_table_exists(where):
    assert len(_layout_rows(TABLES[where])) >= 10, "the layout table was not found"
    _, missing = _named_by_the_layout(TABLES[where])
    assert not missing, f"{where}'s layout table names paths that do not exist: {missing}"


def _entries(folder: Path) -> list[Path]:
    return [
        p
        for p in sorted(folder.iterdir())
        if not p.name.startswith((".", "__"))
        and p.suffix not in (".pyc", ".egg-info")
        and p.name not in ("py.typed",)
    ]


def test_the_layout_table_names_every_package_module_and_top_directory():
    """Every package of src/acordcs at any depth and every module at its top, and every entry of
    tools/, samples/, benchmarks/, deploy/ and docs/, is named by the table of docs/layout.md."""
    named, _ = _named_by_the_layout(MODULES)
    package = ROOT / "src" / "acordcs"
    wanted = [p for p in package.rglob("__init__.py") if p.parent != package]
    wanted = [p.parent for p in wanted] + [
        p for p in package.glob("*.py") if p.name != "__init__.py"
    ]
    for top in ("tools", "samples", "benchmarks", "deploy", "docs"):
        wanted += _entries(ROOT / top)
    unnamed = sorted(str(p.relative_to(ROOT)) for p in wanted if p not in named)
    assert not unnamed, f"docs/layout.md's table does not name: {unnamed}"


# --------------------------------------------------------------------- the README stands alone
def _paths_with_their_directory() -> list[tuple[str, Path]]:
    """Every relative path written with ``..`` in the README, with the directory it is relative
    to: the README's own directory, or in a transcript the directory its last ``cd`` entered."""
    found = []
    inside = False
    here = ROOT
    for line in README.splitlines():
        if line.startswith("```"):
            inside, here = not inside, ROOT
            continue
        entered = re.search(r"(?:^|\$ |&& |; )cd (\S+)", line) if inside else None
        if entered:
            here = Path(os.path.normpath(here / entered.group(1)))
        for path in re.findall(r"[\w./-]*\.\./[\w./-]*", line):
            found.append((path, here))
    return found


def test_the_readme_names_no_path_outside_the_repository():
    """A reader has the repository, nothing beside it: a path that climbs out of it (a paper, a
    reference export, another checkout) is a path the reader does not have. The ``make demo``
    transcript's paths relative to ``samples/weblab``, where it runs, stay inside."""
    paths = _paths_with_their_directory()
    outside = [p for p, here in paths if not Path(os.path.normpath(here / p)).is_relative_to(ROOT)]
    assert not outside, f"the README names paths outside the repository: {outside}"
    assert not re.search(r"/work/|/home/|/tmp/|~/", README), "an absolute path of one machine"


def test_the_readme_links_every_page_of_the_documentation():
    linked = set(re.findall(r"\]\(docs/([\w-]+\.md)(?:#[\w-]+)?\)", README))
    pages = {p.name for p in (ROOT / "docs").glob("*.md")} - {"index.md"}
    assert pages <= linked, f"pages the README does not link: {sorted(pages - linked)}"
