"""The XPath cost check follows which node-sets hold at most one node (a comparison or a union of
two that may each hold many is refused: quadratic), through parentheses, predicates, ``self``,
``..`` and ``ancestor`` steps, and what a node reached by ``..`` inside a predicate may do; and a
refusal says where (line 1, the column of what it refuses; 1 for a cost over the limit).

Each figure is the rules of ``test_context_xpath_cost_model_is_pinned.py`` summed by hand (a
step, a reading, a node-set result: 8 units; an operator, a literal, a call, a predicate: 1;
each character a ``contains`` looks for: 16). They are what mutants of ``xpathcost.py`` that
survived its other tests change."""

from __future__ import annotations

import pytest

from acordcs.runtime.context import SubscriptionError
from acordcs.runtime.context.xpathcost import check_cost, expression_cost

S = R = N = 8  # a step, a reading, a node-set result
O = L = C = 1  # an operator, a literal, a call  # noqa: E741


@pytest.mark.parametrize(
    ("xpath", "cost"),
    [
        # the document's self is the document: its element child is one node
        ("/self::node()/robot = //alarm", O + 2 * S + 2 * S + 2 * R),
        # the context node's parent is one node, and so is its parent
        (".. = //alarm", O + S + 2 * S + 2 * R),
        ("../..", 2 * S + N),
        ("../battery", 2 * S + N),
        ("ancestor::robot", S + N),
        # an empty literal is no character to look for: 'ab' is two
        ("contains(., concat('', 'ab'))", C + S + C + 2 * L + R + 2 * 16),
    ],
)
def test_what_holds_one_node_is_compared_at_its_exact_cost(xpath: str, cost: int) -> None:
    assert expression_cost(xpath) == cost


def test_a_cost_is_a_whole_number_of_units() -> None:
    cost = expression_cost("concat(., @a, 'x')")  # 3 arguments: 3 copies of a pass
    assert cost == C + S + S + L + 2 * R + 3 * 8
    assert type(cost) is int


@pytest.mark.parametrize(
    "xpath",
    [
        # a child of one node may be many nodes, however the one node was reached
        "/robot/battery = //alarm",
        "(/robot)/battery = //alarm",
        "(/robot)[1]/battery = //alarm",
        "/robot[1]/battery = //alarm",
        "self::node()/battery = //alarm",
    ],
)
def test_children_of_one_node_compared_with_many_are_refused(xpath: str) -> None:
    with pytest.raises(SubscriptionError, match="compares two node-sets with '='"):
        expression_cost(xpath)


def test_a_union_of_a_union_and_many_nodes_is_refused() -> None:
    assert expression_cost("/robot | //alarm") == O + S + 2 * S + N
    with pytest.raises(SubscriptionError, match="unites two node-sets that may each hold many"):
        expression_cost("(/robot | //alarm) | //event")


def test_a_union_with_the_parent_inside_a_predicate_reads_the_parent() -> None:
    with pytest.raises(SubscriptionError, match=r"reached by the parent axis \('..'\)") as refused:
        expression_cost("//alarm[(.. | @zone) = 'x']")
    assert refused.value.column == len("//alarm[(.. | @zone) ") + 1  # the comparison


def test_refusals_say_line_1_and_a_cost_over_the_limit_column_1() -> None:
    with pytest.raises(SubscriptionError) as over:
        check_cost("//alarm/@zone", 31)
    assert (over.value.line, over.value.column) == (1, 1)
    assert "costs 32 units, more than the limit of 31" in str(over.value)
    assert check_cost("//alarm/@zone", 32) == 32
    with pytest.raises(SubscriptionError) as refused:
        check_cost("//alarm[id('x')]", 1000)
    assert (refused.value.line, refused.value.column) == (1, 9)
