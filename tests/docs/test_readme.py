"""The README tells the truth: its codes table matches the tools (its `make demo` transcript is
checked by tests/samples/weblab/test_make_demo.py, beside the demo's other tests)."""

from __future__ import annotations

import re
import subprocess
import sys

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
