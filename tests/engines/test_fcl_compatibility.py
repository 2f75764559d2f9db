"""FCL files as real projects write them (issue 14, FCL compatibility): what jFuzzyLogic reads we
read the same way, and what we do not support is said plainly at file:line:column, once."""

from __future__ import annotations

import pytest

from acordcs.engines.fuzzy import read_fcl, write_fcl
from acordcs.engines.rule_engine import RuleError

HEAD = "FUNCTION_BLOCK t\nVAR_INPUT x : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"  # 1-3


def _fcl(
    fuzzify: str = "TERM a := trian 0 2 4; TERM c := trian 4 6 8;",
    defuzzify: str = "TERM b := trian 0 2 4; TERM d := trian 6 8 10;",
    rules: str = "RULE 1 : IF x IS a THEN y IS b;",
    head: str = HEAD,
    extra: str = "",
) -> str:
    return (
        head
        + f"FUZZIFY x\n  {fuzzify}\n  RANGE := (0 .. 10);\nEND_FUZZIFY\n"  # 4-7
        + f"DEFUZZIFY y\n  {defuzzify}\n  RANGE := (0 .. 10);\nEND_DEFUZZIFY\n"  # 8-11
        + extra
        + f"RULEBLOCK r\n  {rules}\nEND_RULEBLOCK\nEND_FUNCTION_BLOCK\n"
    )


def _fire(text: str, x: float, output: str = "y") -> float:
    engine = read_fcl(text)["t"]
    engine.set("x", x)
    engine.fire("r")
    return engine.get(output)


def test_two_rules_with_one_number_are_both_kept() -> None:
    same = _fcl(rules="RULE 1 : IF x IS a THEN y IS b; RULE 1 : IF x IS c THEN y IS d;")
    apart = _fcl(rules="RULE 1 : IF x IS a THEN y IS b; RULE 2 : IF x IS c THEN y IS d;")
    engine = read_fcl(same)["t"]
    assert [e.label for e in engine.rules("r")] == ["1", "1.2"]
    for x in (1.0, 4.0, 6.0):
        assert _fire(same, x) == _fire(apart, x)
    again = read_fcl(write_fcl(engine))["t"]  # the second label reads back (a number)
    assert [e.label for e in again.rules("r")] == ["1", "1.2"]


def test_an_output_with_default_that_no_rule_concludes_reads_its_default() -> None:
    head = HEAD.replace("VAR_OUTPUT y : REAL;", "VAR_OUTPUT y : REAL; w : REAL;")
    extra = "DEFUZZIFY w\n  TERM e := trian 0 1 2;\n  DEFAULT := 7;\nEND_DEFUZZIFY\n"
    assert _fire(_fcl(head=head, extra=extra), 1.0, "w") == 7.0


def test_an_unused_input_without_terms_or_range_loads() -> None:
    head = HEAD.replace("VAR_INPUT x : REAL;", "VAR_INPUT x : REAL; unused : REAL;")
    assert _fire(_fcl(head=head), 2.0) == pytest.approx(2.0)
    rules = "RULE 1 : IF x IS a AND unused IS a THEN y IS b;"
    with pytest.raises(RuleError, match="variable unused has no terms") as caught:
        read_fcl(_fcl(head=head, rules=rules), filename="u.fcl")
    assert str(caught.value).startswith("u.fcl:13:")


@pytest.mark.parametrize("spike", ["TRIAN 5 5 5", "TRAPE 5 5 5 5", "(5, 0) (5, 1)"])
def test_a_zero_width_input_term_is_a_spike(spike: str) -> None:
    text = _fcl(fuzzify=f"TERM a := {spike}; TERM c := trian 4 6 8;")
    assert _fire(text, 5.0) == pytest.approx(2.0)  # a fires fully: y is b, centroid 2
    assert _fire(text, 5.5) == 0.0  # a is 0 beside its spike: no rule fires, y is its low end


@pytest.mark.parametrize("spike", ["TRIAN 7 7 7", "TRAPE 7 7 7 7", "(7, 0) (7, 1)", "7"])
def test_a_spike_beside_shaped_output_terms_is_read_and_seen_by_no_method(spike, caplog) -> None:
    """jFuzzyLogic samples a continuous output on 1,001 points
    (net.sourceforge.jFuzzyLogic.defuzzifier.DefuzzifierContinuous, RuleActivationMethod.imply):
    a zero-width triangle (MembershipFunctionTriangular.membership: 1 only at x == mid) adds
    nothing unless a sample falls exactly on it. Exactly: it has no width, for every method."""
    both = "RULE 1 : IF x IS a THEN y IS b; RULE 2 : IF x IS a THEN y IS d;"
    text = _fcl(defuzzify=f"TERM b := trian 0 2 4; TERM d := {spike};", rules=both)
    for method in ("COG", "COA", "LM", "RM", "MM"):
        mixed = text.replace(
            "RANGE := (0 .. 10);\nEND_DEFUZZIFY",
            f"RANGE := (0 .. 10);\n  METHOD : {method};\nEND_DEFUZZIFY",
        )
        alone = mixed.replace("RULE 2 : IF x IS a THEN y IS d;", "")
        assert _fire(mixed, 1.0) == _fire(alone, 1.0)
    assert "<input>:9:36: 1 singleton or zero-width term(s) of output y beside" in caplog.text
    only = _fcl(
        defuzzify=f"TERM b := trian 0 2 4; TERM d := {spike};",
        rules="RULE 2 : IF x IS a THEN y IS d;",
    )
    assert (
        _fire(only, 1.0) == 0.0
    )  # only the spike fired: as if no rule fired (y keeps its low end)


def test_zero_width_output_terms_are_singletons() -> None:
    text = _fcl(
        fuzzify="TERM a := trian 0 2 4; TERM c := trian 3 6 8;",
        defuzzify="TERM b := TRIAN 2 2 2; TERM d := (8, 0) (8, 1);",
        rules="RULE 1 : IF x IS a THEN y IS b; RULE 2 : IF x IS c THEN y IS d;",
    )
    assert _fire(text, 2.0) == 2.0
    a, c = 0.25, 0.5 / 3  # at x = 3.5
    assert _fire(text, 3.5) == pytest.approx((a * 2 + c * 8) / (a + c))


@pytest.mark.parametrize(
    ("text", "words", "line", "column"),
    [
        (
            _fcl(fuzzify="TERM a := trian 0 2 4; TERM f := FUNCTION (x + 1);"),
            "a FUNCTION term in FUZZIFY is 1 only where the input equals",
            5,
            36,
        ),
        (
            "FUNCTION f : REAL\nVAR_INPUT a : REAL; END_VAR\nf := a;\nEND_FUNCTION\n" + _fcl(),
            "FUNCTION definitions \\(IEC 61131-3 program code\\) are not read",
            1,
            1,
        ),
        (
            _fcl(defuzzify="TERM b := trian 0 2 4; ACCU : MAX;"),
            "ACCU inside DEFUZZIFY y is fuzzylite's dialect .* move ACCU : MAX; into the RULEBLOCK",
            9,
            26,
        ),
        (
            _fcl(defuzzify="TERM b := trian 0 2 4; DEFAULT := nan;"),
            "DEFAULT := nan is fuzzylite's dialect .* write DEFAULT := NC",
            9,
            37,
        ),
        (_fcl(defuzzify="TERM b := trian 4 2 0;"), "variable 'y', term 'b': triangle", 9, 13),
        (
            _fcl(head=HEAD.replace("VAR_OUTPUT y : REAL;", "VAR_OUTPUT y : REAL; w : REAL;")),
            "output w has no DEFUZZIFY block",
            3,
            22,
        ),
        (_fcl() + _fcl(), "two FUNCTION_BLOCKs are named 't'", 16, 1),
    ],
)
def test_what_is_unsupported_is_said_at_file_line_column_once(text, words, line, column) -> None:
    with pytest.raises(RuleError, match=words) as caught:
        read_fcl(text, filename="c.fcl")
    err = caught.value
    assert (err.line, err.column) == (line, column)
    assert str(err).startswith(f"c.fcl:{line}:{column}: error: ")
    assert str(err).count("c.fcl") == 1, str(err)
