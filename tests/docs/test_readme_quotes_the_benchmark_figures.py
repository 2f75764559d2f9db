"""One source of truth for the benchmark figures: every figure the README states is quoted from
docs/benchmarks.md, present there and equal (the same number, range and unit)."""

from __future__ import annotations

import re

from tests.support.toolchain import ROOT

README = (ROOT / "README.md").read_text(encoding="utf-8")
PAGE = (ROOT / "docs" / "benchmarks.md").read_text(encoding="utf-8")
NUMBER = r"\d+(?:,\d{3})*(?:\.\d+)?"
# Units of speed, wherever the README states them; in the benchmark table, any unit or none.
SPEED_UNITS = r"simulated s per wall s|documents/s|inferences/s|us|ms|B|x"
TABLE_UNITS = rf"{SPEED_UNITS}|times|MB|s|%"


def _figures(text: str, units: str, *, unitless: bool) -> list[str]:
    """Each figure of ``text``: a number or a range ('N to M') and its unit ('4.02 to 5.17 B',
    '678x', '11 % drop' -> '11 %'); a bare number only when ``unitless``."""
    pattern = re.compile(
        rf"(?<![\w.,]){NUMBER}(?:\s+to\s+{NUMBER})?(?:\s?(?:{units})(?![\w/]))"
        + ("?" if unitless else "")
    )
    return [m.group(0) for m in pattern.finditer(text)]


def _flat(text: str) -> str:
    return re.sub(r"\s+", " ", text.replace("**", ""))


def _stated(figure: str, page: str) -> bool:
    """The figure is in the page as a figure of its own: '3 B' is not found in '13 B', nor '0.7'
    in '0.75'."""
    return re.search(rf"(?<![\w.,]){re.escape(figure)}(?![\w]|[.,]\d)", page) is not None


def _benchmark_table() -> str:
    section = README.split("\n## Benchmarks\n", 1)[1]
    return "\n".join(line for line in section.splitlines() if line.startswith("| "))


def test_the_readme_quotes_its_benchmark_table_from_docs_benchmarks():
    table = _benchmark_table()
    figures = _figures(table, TABLE_UNITS, unitless=True)
    assert len(figures) > 40, "the README's benchmark table was not found"
    page = _flat(PAGE)
    missing = [f for f in figures if not _stated(f, page)]
    assert not missing, (
        f"README figures not in docs/benchmarks.md as the README states them: {missing}"
    )


def test_every_speed_figure_of_the_readme_is_in_docs_benchmarks():
    """Wherever the README states a speed (the demo's transcript included), docs/benchmarks.md
    states the same."""
    figures = _figures(_flat(README), SPEED_UNITS, unitless=False)
    assert any("simulated s per wall s" in f for f in figures), "the demo's speed was not found"
    page = _flat(PAGE)
    missing = [f for f in figures if not _stated(f, page)]
    assert not missing, (
        f"README figures not in docs/benchmarks.md as the README states them: {missing}"
    )


def test_b_is_defined_where_the_readme_and_the_benchmarks_page_first_use_it():
    definition = "the time lxml takes to parse and re-serialise the same model file"
    for name, text in (("README.md", README), ("docs/benchmarks.md", PAGE)):
        flat = _flat(text)
        first_use = re.search(rf"(?<![\w.,]){NUMBER} B\b|\bin B\b|\bof B\b", flat)
        assert first_use, f"{name} does not use B"
        defined = flat.find(definition, max(0, first_use.start() - 300))
        assert defined != -1 and defined - first_use.start() < 300, (
            f"{name} does not define B where it first uses it"
        )
