"""A scenario's steps from a CSV file beside it: rows become steps, a bad cell is refused at its
line and column, and a file outside the scenario file's directory is not read."""

from __future__ import annotations

from pathlib import Path

from tests.support.toolchain import SAMPLES, run_main

GREENHOUSE = str(SAMPLES / "tutorial" / "greenhouse.uml")
SCENARIO = """scenarios:
  - name: a day from a CSV trace
    csv: {csv}
    steps: [{{at: 5000, set: {{Climate.temperature: 27}}}}]
    expect:
      - {{at: 3600, term: {{Vent.opening: half}}}}
      - {{at: 5000, term: {{Vent.opening: half}}}}
      - {{at: 7200, term: {{Vent.opening: wide}}}}
      - {{from: 0, to: 3599, term: {{Vent.opening: closed}}}}
"""


def write(folder: Path, rows: str, csv: str = "day.csv") -> Path:
    (folder / "day.csv").write_text("# degrees Celsius\ntime, Climate.temperature\n" + rows)
    path = folder / "day.yaml"
    path.write_text(SCENARIO.format(csv=csv), encoding="utf-8")
    return path


def test_the_rows_are_steps_merged_with_the_scenarios_own(tmp_path: Path):
    result = run_main(["test", GREENHOUSE, str(write(tmp_path, "0,10\n3600,26\n7200,38\n"))])
    assert result.code == 0, result.out + result.err
    assert "(4 steps, 4 expectations" in result.out


def test_a_bad_cell_is_refused_at_its_line_and_column(tmp_path: Path):
    path = write(tmp_path, "0,10\n3600, 99\n")
    result = run_main(["test", GREENHOUSE, str(path)])
    assert result.code == 2
    assert result.err.startswith(
        f"{tmp_path / 'day.csv'}:4:7: error: S805 Climate.temperature = 99 is outside its range 0..50"
    )


def test_a_file_outside_the_scenario_files_directory_is_not_read(tmp_path: Path):
    inner = tmp_path / "inner"
    inner.mkdir()
    write(tmp_path, "0,10\n")
    path = inner / "day.yaml"
    path.write_text(SCENARIO.format(csv="../day.csv"), encoding="utf-8")
    result = run_main(["test", GREENHOUSE, str(path)])
    assert result.code == 2
    assert (
        f"{path}:3:10: error: S801 the CSV file '../day.csv' is not in the scenario" in result.err
    )
