"""The XPath cost model's values, pinned (issue 36, item 8): the cost check of an untrusted
subscriber's XPath is a security control, and mutation testing killed only 55% of its mutants
because no test asserted an exact cost (doubling or negating an operator's cost, dropping the
refusal of ``id()``, treating ``and``/``or`` as comparisons went unnoticed).

The expected numbers are written from the model's documented rules
(``acordcs.runtime.context.xpathcost``'s docstring, docs/providers.md "Security model"), by
hand, not by running the code: an independent oracle. The rules, in units:

- a location step: 8 (``PASS``, one walk over the document); ``//`` is two steps
  (``/descendant-or-self::node()/``), ``.`` and ``..`` one each;
- a reading of string-values (a node-set compared, converted, given to a function that reads
  it): 8; ``count``, ``name``, ``local-name``, ``namespace-uri``, ``boolean`` and ``not`` do
  not read their argument; ``string``, ``number``, ``string-length`` and ``normalize-space``
  without an argument read the context node;
- each character ``contains``, ``substring-before`` and ``substring-after`` look for (their
  second argument, a literal): 16 (two passes); a number literal counts one character more
  than it is written with (``.5`` is ``0.5``), a ``concat`` of literals the sum of theirs;
- ``concat`` of k arguments, not all literals: the copies libxml2 makes,
  k(k+1)/2 - k passes besides the reading of each node-set argument;
- each operator (``and``, ``or``, ``=``..., ``+``..., ``|``, unary ``-``), literal, predicate
  and function call: 1;
- a node-set result: 8 (its nodes become Python objects).

Then the refusals, whatever the cost: ``id()``, ``lang()``, ``translate()``, functions that
are not XPath 1.0's, variables, the namespace axis, predicates in predicates, paths from the
root and descendant, ancestor, sideways steps inside a predicate, the string-value of or a step
from ``..`` inside a predicate, a step other than child, attribute or self after one that may
select many nodes, unions and comparisons of two node-sets that may both hold many nodes, a
computed needle; and ``and``/``or`` are not comparisons: they read nothing and compare nothing.
"""

from __future__ import annotations

import pytest
from lxml import etree

from acordcs.runtime.context import ContextProvider, Limits, SubscriptionError
from acordcs.runtime.context.xpathcost import (
    NEEDLE,
    PASS,
    UNIT,
    check_cost,
    document_cost,
    expression_cost,
)

S = R = N = 8  # a step, a reading, a node-set result
O = L = C = P = 1  # an operator, a literal, a call, a predicate  # noqa: E741

# (expression, cost): each sum is the rules above, term by term.
COSTS = [
    # -- paths
    ("/", N),  # the root, no step
    ("/robot", S + N),
    ("/robot/battery", 2 * S + N),
    ("//alarm", 2 * S + N),
    ("//alarm/@zone", 3 * S + N),
    (".", S + N),
    ("self::node()", S + N),
    ("/robot/..", 2 * S + N),  # a parent step after one node
    ("/robot/descendant::battery", 2 * S + N),  # a descendant step after one node
    ("/robot/following-sibling::x", 2 * S + N),  # outside a predicate
    # -- predicates
    ("//alarm[1]", 2 * S + P + L + N),
    ("(//alarm)[1]", 2 * S + P + L + N),
    ("//alarm[@zone][@level]", 2 * S + (P + S) + (P + S) + N),
    ("//alarm[text()]", 2 * S + P + S + N),
    ("//alarm[..]", 2 * S + P + S + N),  # a bare '..' reads nothing
    ("//alarm[name(..) = 'r']", 2 * S + P + O + C + S + L + N),  # name() reads nothing
    ("//alarm[count(..) = 1]", 2 * S + P + O + C + S + L + N),
    ("//alarm[position() = last()]", 2 * S + P + O + C + C + N),
    # -- comparisons read their node-sets, not their scalars
    ("//alarm[. = 'x']", 2 * S + P + O + S + L + R + N),
    ("//alarm[@x = @y]", 2 * S + P + O + S + S + R + R + N),
    ("/robot = /robot/battery", O + S + 2 * S + R + R),  # one side is one node
    ("/robot/battery = 'x'", O + 2 * S + L + R),
    ("/robot/battery + 1", O + 2 * S + L + R),
    ("count(//alarm) > 1", O + C + 2 * S + L),
    (
        "//alarm[level/value > 3 and @zone = 'b']",
        2 * S + P + O + (O + 2 * S + L + R) + (O + S + L + R) + N,
    ),
    # -- and/or: an operator each, no reading, node-sets of any size on both sides
    ("//alarm[b and c]", 2 * S + P + O + S + S + N),
    ("//alarm[b or c]", 2 * S + P + O + S + S + N),
    ("//alarm[@x and @y]", 2 * S + P + O + S + S + N),
    ("/robot/a or /robot/b", O + 2 * S + 2 * S),
    ("/robot/a and 1", O + 2 * S + L),
    # -- negation and arithmetic read their operands
    ("-/robot/battery", O + 2 * S + R),
    ("-(1)", O + L),
    ("-count(/robot/a)", O + C + 2 * S),
    ("/robot/a * 2 mod 3", O + (O + 2 * S + L + R) + L),
    ("sum(/robot/a) div 2", O + C + 2 * S + R + L),
    # -- functions
    ("true()", C),
    ("not(true())", C + C),
    ("last()", C),
    ("position()", C),
    ("name()", C),
    ("local-name()", C),
    ("string()", C + R),  # the context node
    ("number()", C + R),
    ("string-length()", C + R),
    ("normalize-space()", C + R),
    ("string-length(/robot)", C + S + R),
    ("name(/robot/a)", C + 2 * S),
    ("count(/robot/a)", C + 2 * S),
    ("boolean(//a)", C + 2 * S),
    ("not(/robot/a)", C + 2 * S),
    ("namespace-uri(/robot/a)", C + 2 * S),
    ("number(/robot/a)", C + 2 * S + R),
    ("floor(/robot/a)", C + 2 * S + R),
    ("ceiling(/robot/a)", C + 2 * S + R),
    ("round(/robot/a)", C + 2 * S + R),
    ("sum(/robot/a)", C + 2 * S + R),
    ("substring(/robot/a, 2, 3)", C + 2 * S + L + L + R),
    ("starts-with(/robot/a, 'abc')", C + 2 * S + L + R),  # no needle: a prefix
    # -- the needle: 16 a character
    ("//*[contains(., 'fire')]", 2 * S + P + C + S + L + R + 4 * 16 + N),
    ("//*[contains(., 'aaaaaaaaab')]", 2 * S + P + C + S + L + R + 10 * 16 + N),
    ("//a[contains(., '')]", 2 * S + P + C + S + L + R + N),
    ("//a[contains(., 12)]", 2 * S + P + C + S + L + R + 3 * 16 + N),  # "12": 2 + 1
    ("//a[contains(., .5)]", 2 * S + P + C + S + L + R + 3 * 16 + N),  # "0.5"
    ("//a[substring-before(., 'x') = 'y']", 2 * S + P + O + C + S + L + R + 16 + L + N),
    ("//a[substring-after(., 'xy')]", 2 * S + P + C + S + L + R + 2 * 16 + N),
    ("//a[contains(., concat('ab', 'c'))]", 2 * S + P + C + S + (C + L + L) + R + 3 * 16 + N),
    # -- concat: k arguments, k(k+1)/2 - k copies besides the readings
    ("concat('ab', 'cd')", C + L + L),  # literals only: a literal
    ("concat(/r/a, 'x')", C + 2 * S + L + R + 8 * (3 - 2)),
    ("concat(/r/a, /r/b)", C + 2 * S + 2 * S + R + R + 8 * (3 - 2)),
    ("concat(/r/a, /r/b, /r/c)", C + 3 * 2 * S + 3 * R + 8 * (6 - 3)),
    # -- unions: one side at most one node
    ("/r/a | /r", O + 2 * S + S + N),
    ("/r | //a", O + S + 2 * S + N),
]


def test_the_constants_are_the_documented_ones():
    assert (PASS, UNIT, NEEDLE) == (8, 1, 16)
    assert Limits().max_xpath_cost == 128


@pytest.mark.parametrize(("xpath", "units"), COSTS, ids=[x for x, _ in COSTS])
def test_each_expression_costs_exactly_what_the_rules_say(xpath: str, units: int):
    assert expression_cost(xpath) == units


def test_the_documented_examples():
    # docs/providers.md, "Security model": the examples it gives
    assert expression_cost("//*[contains(., 'fire')]") == 107
    assert expression_cost("//alarm[level/value > 3 and @zone = 'b']") == 70
    assert expression_cost("count(//alarm) > 1") == 19
    assert expression_cost("//*[contains(., 'aaaaaaaaab')]") == 203


def test_the_limit_is_inclusive_and_the_refusal_gives_the_cost():
    assert check_cost("//*[contains(., 'fire')]", 107) == 107
    with pytest.raises(SubscriptionError, match="costs 107 units, more than the limit of 106"):
        check_cost("//*[contains(., 'fire')]", 106)


def test_an_untrusted_provider_takes_up_to_128_units_and_refuses_129():
    # 2*8 + 1 + 1 + 8 + 1 + 8 + n*16 + 8 = 43 + 16n: n = 5 is 123, n = 6 is 139
    assert expression_cost("//*[contains(., 'aaaab')]") == 123
    assert expression_cost("//*[contains(., 'aaaaab')]") == 139
    provider = ContextProvider()
    try:
        provider.subscribe(print, "//*[contains(., 'aaaab')]")
        with pytest.raises(SubscriptionError, match="costs 139 units, more than the limit of 128"):
            provider.subscribe(print, "//*[contains(., 'aaaaab')]")
    finally:
        provider.close()
    trusted = ContextProvider(Limits(trusted_subscribers=True))
    try:
        trusted.subscribe(print, "//*[contains(., 'aaaaab')]")
        trusted.subscribe(print, "//a[id('x')]")
    finally:
        trusted.close()


REFUSED = [
    ("id('a')", "calls id()"),
    ("//a[id('x')]", "calls id()"),
    ("count(id('x'))", "calls id()"),
    ("lang('en')", "calls lang()"),
    ("//a[lang('en')]", "calls lang()"),
    ("translate(., 'a', 'b')", "calls translate()"),
    ("frobnicate(.)", "calls frobnicate(), which is not an XPath 1.0 core function"),
    ("//a[ext:f(.)]", "calls ext:f(), which is not an XPath 1.0 core function"),
    ("$v", "uses a variable"),
    ("//a[. = $v]", "uses a variable"),
    ("namespace::*", "uses the namespace axis"),
    ("//a[b[c]]", "has a predicate inside a predicate"),
    ("//a[//b]", "has a path from the root inside a predicate"),
    ("//a[/r]", "has a path from the root inside a predicate"),
    ("//a[descendant::b]", "has the descendant axis inside a predicate"),
    ("//a[descendant-or-self::b]", "has the descendant-or-self axis inside a predicate"),
    ("//a[.//b]", "has a descendant step '//' inside a predicate"),
    ("//a[ancestor::b]", "uses the ancestor axis inside a predicate"),
    ("//a[ancestor-or-self::b]", "uses the ancestor-or-self axis inside a predicate"),
    ("//a[following::b]", "uses the following axis inside a predicate"),
    ("//a[following-sibling::b]", "uses the following-sibling axis inside a predicate"),
    ("//a[preceding::b]", "uses the preceding axis inside a predicate"),
    ("//a[preceding-sibling::b]", "uses the preceding-sibling axis inside a predicate"),
    ("//a[string-length(..) = 1]", "reads the string-value of a node reached by the parent"),
    ("//a[.. = 'x']", "reads the string-value of a node reached by the parent"),
    ("//a[count(../b) > 0]", "takes a child step from a node reached by the parent axis"),
    ("//a[../@x = 'y']", "takes a attribute step from a node reached by the parent axis"),
    ("//a//b", "takes a descendant-or-self step from a step that may select many nodes"),
    ("//a/..", "takes a parent step from a step that may select many nodes"),
    ("//a/ancestor::b", "takes a ancestor step from a step that may select many nodes"),
    ("//a/following-sibling::b", "takes a following-sibling step from a step that may select"),
    ("/r/a/preceding::b", "takes a preceding step from a step that may select many nodes"),
    ("//a | //b", "unites two node-sets that may each hold many nodes"),
    ("//a = //b", "compares two node-sets with '='"),
    ("//a[b = c]", "compares two node-sets with '='"),
    ("//a[b != c]", "compares two node-sets with '!='"),
    ("//a[b < c]", "compares two node-sets with '<'"),
    ("//a[b <= c]", "compares two node-sets with '<='"),
    ("//a[b > c]", "compares two node-sets with '>'"),
    ("//a[b >= c]", "compares two node-sets with '>='"),
    ("//a[contains(., concat(., 'b'))]", "gives contains() a computed argument 2"),
    ("//a[contains(., b)]", "gives contains() a computed argument 2"),
    ("//a[substring-before(., b)]", "gives substring-before() a computed argument 2"),
    ("//a[substring-after(., .)]", "gives substring-after() a computed argument 2"),
]


@pytest.mark.parametrize(("xpath", "rule"), REFUSED, ids=[x for x, _ in REFUSED])
def test_each_refusal_names_its_rule_whatever_the_limit(xpath: str, rule: str):
    with pytest.raises(SubscriptionError) as refused:
        check_cost(xpath, 10**9)
    assert rule in str(refused.value), str(refused.value)


def test_the_refusal_names_the_column_of_what_it_refuses():
    for xpath, column in [("//a[id('x')]", 5), ("//a[b = c]", 7), ("//a//b", 4), ("$v", 1)]:
        with pytest.raises(SubscriptionError) as refused:
            check_cost(xpath, 10**9)
        assert refused.value.column == column, (xpath, refused.value.column)


def test_and_or_are_not_comparisons_and_comparisons_are_not_and_or():
    # the same operands: and/or take them and read nothing; a comparison refuses two sets
    for op in ("and", "or"):
        assert expression_cost(f"//a[b {op} c]") == 2 * S + P + O + S + S + N
        assert expression_cost(f"//a[@x {op} @y]") == 2 * S + P + O + S + S + N
    for op in ("=", "!=", "<", "<=", ">", ">="):
        with pytest.raises(SubscriptionError, match=f"compares two node-sets with '{op}'"):
            expression_cost(f"//a[b {op} c]")
        assert expression_cost(f"//a[@x {op} @y]") == 2 * S + P + O + S + S + R + R + N


def test_an_untrusted_provider_refuses_an_unknown_function_at_subscribe():
    provider = ContextProvider()
    try:
        with pytest.raises(SubscriptionError, match=r"calls frobnicate\(\)"):
            provider.subscribe(print, "/robot[frobnicate(battery)]")
        with pytest.raises(SubscriptionError, match=r"calls id\(\)"):
            provider.subscribe(print, "//robot[id('x')]")
    finally:
        provider.close()


DOCUMENTS = [
    # the sum over elements of depth * (1 + length of its text), plus over tails of length
    # times the depth of the element holding them (the parent)
    ("<r/>", 1 * (1 + 0)),
    ("<r>abc</r>", 1 * (1 + 3)),
    ("<r><a>xy</a><b/>tail</r>", 1 * 1 + 2 * (1 + 2) + 2 * 1 + 1 * 4),
    ("<r>ab<a>c</a>d</r>", 1 * (1 + 2) + 2 * (1 + 1) + 1 * 1),
    ("<r><a><b><c>xyz</c></b></a></r>", 1 + 2 + 3 + 4 * (1 + 3)),
]


@pytest.mark.parametrize(("xml", "cost"), DOCUMENTS, ids=[x for x, _ in DOCUMENTS])
def test_a_documents_cost_is_what_the_rule_says(xml: str, cost: int):
    assert document_cost(etree.fromstring(xml)) == cost
