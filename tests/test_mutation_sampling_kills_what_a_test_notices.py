"""``tools/mutation_sample.py`` on a two-function module and its test: every mutant is listed with
its line, the ones the test notices are killed, the others survive and are named, the sample is
the seed's, and the measured tree is left as it was."""

from __future__ import annotations

from pathlib import Path

from tools.mutation_sample import Mutant, measure, mutants, mutated, report, sample

MODULE = """def add(a, b):
    return a + b


def is_big(x: int) -> bool:
    return x > 10
"""
TEST = """from calc import add, is_big


def test_add():
    assert add(2, 3) == 5


def test_is_big():
    assert is_big(100) and not is_big(0)
"""


def test_every_change_is_listed_with_its_line_and_annotations_are_left_alone():
    assert [(m.line, m.change) for m in mutants(MODULE)] == [
        (2, "return None"),
        (2, "'+' -> '-'"),
        (6, "return None"),
        (6, "'>' -> '>='"),
        (6, "10 -> 11"),
    ]
    assert "return x >= 10" in mutated(MODULE, Mutant(3, 6, "'>' -> '>='"))
    assert "return a + b" in mutated(MODULE, Mutant(3, 6, "'>' -> '>='"))
    assert mutated(MODULE, None).count("10") == 1


def test_the_sample_is_the_seeds_and_all_when_there_are_fewer():
    found = mutants(MODULE)
    assert sample(found, 9, seed=1) == found
    drawn = sample(found, 3, seed=36)
    assert drawn == sample(found, 3, seed=36) and len(set(drawn)) == 3
    assert drawn == sorted(drawn, key=lambda m: m.number)


def test_mutants_the_test_notices_are_killed_and_the_others_named(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("PYTEST_DISABLE_PLUGIN_AUTOLOAD", "1")  # a bare pytest starts faster
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "calc.py").write_text(MODULE)
    (tmp_path / "test_calc.py").write_text(TEST)
    result = measure(
        tmp_path,
        "src/calc.py",
        ["test_calc.py"],
        pytest_args=("-x", "-q", "-p", "no:cacheprovider"),
    )
    outcomes = {(m.line, m.change): o for m, o in result.outcomes.items()}
    assert outcomes == {
        (2, "return None"): "killed",
        (2, "'+' -> '-'"): "killed",
        (6, "return None"): "killed",
        (6, "'>' -> '>='"): "survived",  # no test at the boundary
        (6, "10 -> 11"): "survived",
    }
    assert (result.total, result.score) == (5, 3 / 5)
    table = report([result])
    assert "src/calc.py" in table and "5 of 5" in table and "60%" in table
    assert "line    6  '>' -> '>='  (mutant 3)" in table
    assert (tmp_path / "src" / "calc.py").read_text() == MODULE  # never left mutated
