"""A rule nested (or chained) deeper than ``MAX_DEPTH`` is a syntax error naming the limit: the
parser refuses it, so ``validate`` reports it, instead of the engines' recursive compilers running
out of stack at run time (issue 14, item 7)."""

from __future__ import annotations

import pytest

from acordcs.rules import MAX_DEPTH, RuleSyntaxError, parse_rule, rule_too_deep
from tests.support.toolchain import rule_and_tag_findings

N = 1000


def _chains(n: int) -> dict[str, tuple[str, str]]:
    return {
        "fuzzy and": ("fuzzy", "if " + " and ".join(["x is low"] * n) + " then y is high"),
        "fuzzy not": ("fuzzy", "if " + "not (" * n + "x is low" + ")" * n + " then y is high"),
        "crisp and": ("crisp", "if " + " and ".join(["x > 1"] * n) + " then y = 1"),
        "crisp plus": ("crisp", "if x > " + " + ".join(["1"] * n) + " then y = 1"),
        "crisp minus": ("crisp", "if x > " + "-" * n + "1 then y = 1"),
        "crisp not": ("crisp", "if " + "not " * n + "x > 1 then y = 1"),
        "action plus": ("crisp", "if x > 1 then y = " + " + ".join(["x"] * n)),
        "call argument": ("crisp", "if x > 1 then A.op(" + "-" * n + "x)"),
    }


@pytest.mark.parametrize("case", sorted(_chains(N)))
def test_a_chain_of_a_thousand_is_refused_naming_the_limit(case: str) -> None:
    kind, text = _chains(N)[case]
    with pytest.raises(RuleSyntaxError) as caught:
        parse_rule(text, kind)  # type: ignore[arg-type]
    assert f"limit of {MAX_DEPTH} levels" in caught.value.message
    assert caught.value.column is not None and 1 <= caught.value.column <= len(text)


@pytest.mark.parametrize("case", sorted(_chains(N)))
def test_a_chain_at_the_limit_parses(case: str) -> None:
    # n operators of a chain make n levels (n + 1 operands); `y = -...-x` and the call have no
    # comparison above them, the others one
    kind, text = _chains(MAX_DEPTH - 1)[case]
    rule = parse_rule(text, kind)  # type: ignore[arg-type]
    assert rule_too_deep(rule) is None  # within the limit...
    assert rule_too_deep(rule, MAX_DEPTH - 3) is not None  # ...and at its edge (198 to 200 levels)


def test_a_wide_shallow_rule_of_100_kb_parses() -> None:
    # balanced parentheses: 4096 comparisons, 12 levels of `and`/`or`
    terms = ["x > 1"] * 4096
    while len(terms) > 1:
        terms = [f"({a} and {b})" for a, b in zip(terms[::2], terms[1::2], strict=True)]
    text = f"if {terms[0]} then y = 1"
    assert len(text) > 30_000
    parse_rule(text, "crisp")


def test_validate_reports_the_deep_rule_with_the_limit(tmp_path) -> None:
    deep = "if " + " and ".join(["speed > 1"] * N) + " then count = 1"

    def build(gen, pkg):
        comp = gen.ctx(pkg.cls("Comp"), "CtxComponent")
        comp.attr("speed", "double")
        comp.attr("count", "int")
        pset = gen.ctx(pkg.cls("Set"), "CtxPolicySet", engine="clips", trigger="event")
        policy = gen.ctx(pkg.cls("SetRules"), "CtxPolicy", Rule=deep)
        pkg.associate(pset, policy, "policy", aggregation="composite")
        pkg.depend(pset, comp)

    found = rule_and_tag_findings(tmp_path, build)
    assert [code for code, _ in found] == ["L401"], found
    assert f"the rule nests deeper than the limit of {MAX_DEPTH} levels" in found[0][1]
