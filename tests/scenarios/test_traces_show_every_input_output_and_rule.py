"""``acordcs-gen test --trace DIR``: per scenario a CSV whose rows are the run's samples (every
input, output and rule degree) and its plot as SVG and PNG; a clear error when matplotlib is
missing, before anything runs."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from lxml import etree

from tests.support.toolchain import SAMPLES, run_main

GREENHOUSE = str(SAMPLES / "tutorial" / "greenhouse.uml")
DAY = """scenarios:
  - name: a day
    steps:
      - {at: 0, set: {Climate.temperature: 10}}
      - {at: 60, set: {Climate.temperature: 26}}
      - {at: 120, set: {Climate.temperature: 22}}
"""


def test_the_trace_holds_each_sample_and_the_plots_are_drawn(tmp_path: Path):
    scenario = tmp_path / "day.yaml"
    scenario.write_text(DAY, encoding="utf-8")
    result = run_main(["test", GREENHOUSE, str(scenario), "--trace", str(tmp_path / "trace")])
    assert result.code == 0, result.out + result.err
    stem = tmp_path / "trace" / "day-01-a-day"
    with open(stem.with_suffix(".csv"), encoding="utf-8") as handle:
        table = list(csv.DictReader(handle))
    firings = [row for row in table if row["after"] == "Ventilation"]
    assert [float(row["Climate.temperature"]) for row in firings] == [10.0, 26.0, 22.0]
    # the degrees are the rules' memberships at the input (trapezoid 0 0 18 24, triangle 20 26 32)
    cool, warm = (float(firings[2][f"Ventilation.VentRules.{r}"]) for r in ("cool", "warm"))
    assert cool == pytest.approx((24 - 22) / 6) and warm == pytest.approx((22 - 20) / 6)
    assert float(firings[1]["Vent.opening"]) == pytest.approx(50.0)
    assert [row["time_s"] for row in table if row["after"] == "step"] == ["0.0", "60.0", "120.0"]
    svg = etree.parse(str(stem.with_suffix(".svg")))
    assert svg.getroot().tag == "{http://www.w3.org/2000/svg}svg"
    texts = "".join(svg.getroot().itertext())  # text kept as text, not as glyph paths
    assert "virtual time (s)" in texts and "VentRules.warm" in texts
    assert stem.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_without_matplotlib_trace_is_refused_before_anything_runs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    import acordcs.scenarios.trace_files as trace_files

    monkeypatch.setattr(trace_files, "plots_available", lambda: False)
    scenario = tmp_path / "day.yaml"
    scenario.write_text(DAY, encoding="utf-8")
    result = run_main(["test", GREENHOUSE, str(scenario), "--trace", str(tmp_path / "trace")])
    assert result.code == 2 and result.out == ""
    assert "pip install 'acordcs[plots]'" in result.err
    assert not (tmp_path / "trace").exists()
