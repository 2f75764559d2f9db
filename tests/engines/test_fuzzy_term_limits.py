"""The fuzzy engine's limits on a linguistic variable (issue 22, item 4): 1,000 terms per variable
and 500 points per point list (``acordcs.rules.tree``), said as an error by ``define_variable``, by
the FCL reader at the first term too many (file:line:column), and by the model checks (T315) with
the same numbers; never a hang or a compiler crash."""

from __future__ import annotations

import pytest

from acordcs.engines.fuzzy import FuzzyEngine, read_fcl
from acordcs.engines.rule_engine import RuleError
from acordcs.rules.tree import MAX_POINTS, MAX_TERMS
from tests.support.toolchain import rule_and_tag_findings


def _terms(count: int) -> str:
    return "; ".join(f"t{k} := trian {k} {k + 1} {k + 2}" for k in range(count))


def test_a_variable_at_the_limit_is_taken_and_one_more_is_refused() -> None:
    engine = FuzzyEngine()
    engine.define_variable("y", 0, MAX_TERMS + 2, _terms(MAX_TERMS))
    with pytest.raises(RuleError, match=r"variable 'z' has 1,001 terms; .* at most 1,000 per"):
        engine.define_variable("z", 0, MAX_TERMS + 2, _terms(MAX_TERMS + 1))


def test_a_point_list_beyond_the_limit_is_refused_before_code_is_generated() -> None:
    """5,000 points made the generated membership nest 5,000 branches: RecursionError in fire."""
    engine = FuzzyEngine()
    points = lambda n: " ".join(f"({i}, {i % 2})" for i in range(n))  # noqa: E731
    engine.define_variable("x", 0, 5000, f"a := {points(MAX_POINTS)}")
    with pytest.raises(RuleError, match=r"a point list of 5,000 points; .* at most 500 per term"):
        engine.define_variable("w", 0, 5000, f"a := {points(5000)}")


def test_the_fcl_reader_stops_at_the_first_term_too_many() -> None:
    terms = "\n".join(f"  TERM o{k} := TRIAN {k} {k + 1} {k + 2};" for k in range(MAX_TERMS + 50))
    text = (
        "FUNCTION_BLOCK b\nVAR_INPUT x : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
        f"FUZZIFY x\n  TERM a := TRIAN 0 1 2;\nEND_FUZZIFY\nDEFUZZIFY y\n{terms}\nEND_DEFUZZIFY\n"
        "END_FUNCTION_BLOCK\n"
    )
    with pytest.raises(RuleError, match="DEFUZZIFY y has more than 1,000 terms") as caught:
        read_fcl(text, filename="big.fcl")
    assert (caught.value.line, caught.value.column) == (8 + MAX_TERMS, 3)  # the 1,001st TERM


def test_the_model_check_says_it_with_the_same_numbers(tmp_path) -> None:
    many = _terms(MAX_TERMS + 1)
    long = "a := " + " ".join(f"({i}, {i % 2})" for i in range(MAX_POINTS + 1))

    def build(gen, pkg):
        c = gen.ctx(pkg.cls("Comp"), "CtxComponent")
        for name, terms in (("many", many), ("long", long), ("fine", _terms(MAX_TERMS))):
            c.attr(name, "double", stereotype="ACORDCS:CtxVariable",
                   tags=gen.stereotype_tags("CtxVariable", min="0", max="1002", terms=terms))  # fmt: skip

    found = [(code, msg) for code, msg in rule_and_tag_findings(tmp_path, build) if code == "T315"]
    assert found == [
        (
            "T315",
            "variable 'many' has 1,001 terms; the fuzzy engine takes at most 1,000 per variable "
            "(every firing and the generated rule set grow with them); merge terms or split the "
            "variable",
        ),
        (
            "T315",
            "term 'a' of 'long' is a point list of 501 points; the fuzzy engine takes at most 500 "
            "per term (its generated code has a branch per point); simplify the shape",
        ),
    ]
