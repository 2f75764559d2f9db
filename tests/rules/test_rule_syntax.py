"""The ACORD-CS rule language (acordcs.rules.parser + rules.lark): fuzzy and crisp rules, term lists,
error columns, and a round trip through a printer written here."""

from __future__ import annotations

import dataclasses

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.rules import (
    KEYWORDS,
    Arith,
    Assign,
    BoolOp,
    Call,
    Compare,
    Consequent,
    Const,
    Is,
    Name,
    Neg,
    Not,
    RuleSyntaxError,
    TermDef,
    VarRef,
    names_in,
    parse_rule,
    parse_terms,
    split_rules,
)


def strip(node):
    """A tree without columns (for comparing trees built from different texts)."""
    if isinstance(node, Name):
        return ("Name", node.text)
    if dataclasses.is_dataclass(node):
        fields = [f.name for f in dataclasses.fields(node) if f.name not in ("text", "column")]
        return (type(node).__name__, *(strip(getattr(node, f)) for f in fields))
    if isinstance(node, tuple | list):
        return tuple(strip(n) for n in node)
    return node


def all_names(node) -> list[Name]:
    if isinstance(node, Name):
        return [node]
    if dataclasses.is_dataclass(node):
        return [n for f in dataclasses.fields(node) for n in all_names(getattr(node, f.name))]
    if isinstance(node, tuple | list):
        return [n for item in node for n in all_names(item)]
    return []


def is_(var, term, *hedges):
    return Is(Name(var, 0), tuple(hedges), Name(term, 0))


def cons(var, term):
    return Consequent(Name(var, 0), Name(term, 0))


def var(name):
    return VarRef(Name(name, 0))


# ------------------------------------------------------------------------------------------ fuzzy
def test_paper_rule_with_label() -> None:
    rule = parse_rule(
        "slow1: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is slow"
    )
    assert rule.kind == "fuzzy" and rule.label == "slow1" and rule.weight == 1.0
    assert strip(rule.condition) == strip(
        BoolOp("and", is_("cycleRate", "small"), is_("angle", "narrow"))
    )
    assert strip(rule.actions) == strip((cons("Locomotion.maxSpeed", "slow"),))
    assert [n.text for n in rule.variables_read()] == ["cycleRate", "angle"]
    assert [n.text for n in rule.variables_written()] == ["Locomotion.maxSpeed"]
    assert rule.actions[0].var.element == "Locomotion" and rule.actions[0].var.member == "maxSpeed"


def test_hedges_stack_in_order() -> None:
    rule = parse_rule("if a is not very somewhat high then b is x")
    assert rule.condition.hedges == ("not", "very", "somewhat")
    assert rule.condition.term.text == "high"
    assert parse_rule("if a is very very high then b is x").condition.hedges == ("very", "very")


def test_and_or_equal_precedence_left_to_right() -> None:
    # a and b or c  ==  (a and b) or c ;  a or b and c  ==  (a or b) and c
    r1 = parse_rule("if a is x and b is y or c is z then d is w")
    assert strip(r1.condition) == strip(
        BoolOp("or", BoolOp("and", is_("a", "x"), is_("b", "y")), is_("c", "z"))
    )
    r2 = parse_rule("if a is x or b is y and c is z then d is w")
    assert strip(r2.condition) == strip(
        BoolOp("and", BoolOp("or", is_("a", "x"), is_("b", "y")), is_("c", "z"))
    )


def test_parentheses_group_and_not_applies_to_a_group() -> None:
    rule = parse_rule("if a is x or (b is y and c is z) then d is w")
    assert strip(rule.condition) == strip(
        BoolOp("or", is_("a", "x"), BoolOp("and", is_("b", "y"), is_("c", "z")))
    )
    rule = parse_rule("if not (a is x or b is y) then d is w")
    assert strip(rule.condition) == strip(Not(BoolOp("or", is_("a", "x"), is_("b", "y"))))
    assert strip(parse_rule("if ((a is x)) then d is w").condition) == strip(is_("a", "x"))


def test_several_consequents_and_weight() -> None:
    rule = parse_rule("r: if a is x then b is y and c is z with 0.25")
    assert strip(rule.actions) == strip((cons("b", "y"), cons("c", "z")))
    assert rule.weight == 0.25
    assert parse_rule("if a is x then b is y with 1").weight == 1.0
    assert parse_rule("if a is x then b is y with .5").weight == 0.5


def test_weight_outside_unit_interval() -> None:
    with pytest.raises(RuleSyntaxError) as err:
        parse_rule("if a is x then b is y with 1.5")
    assert "outside" in err.value.message and err.value.column == 23


def test_keywords_are_case_insensitive() -> None:
    lower = parse_rule("if a is not very x and b is y or c is z then d is w with 0.5")
    upper = parse_rule("IF a IS NOT VERY x AND b Is y Or c iS z THEN d IS w WITH 0.5")
    assert strip(upper.condition) == strip(lower.condition)
    assert strip(upper.actions) == strip(lower.actions)
    assert upper.weight == lower.weight == 0.5
    assert upper.condition.left.left.hedges == ("not", "very")
    # names keep their case
    assert parse_rule("if Speed is High then Out is Low").condition.term.text == "High"


def test_crisp_rule_of_the_sample() -> None:
    rule = parse_rule(
        "retry: if Control.speed == 0 and Recovery.retries < 3 then Recovery.recover() "
        "and Recovery.retries = Recovery.retries + 1",
        "crisp",
    )
    assert rule.kind == "crisp" and rule.label == "retry"
    assert strip(rule.condition) == strip(
        BoolOp(
            "and",
            Compare("==", var("Control.speed"), Const(0)),
            Compare("<", var("Recovery.retries"), Const(3)),
        )
    )
    call, assign = rule.actions
    assert strip(call) == strip(Call(Name("Recovery.recover", 0), ()))
    assert strip(assign) == strip(
        Assign(Name("Recovery.retries", 0), Arith("+", var("Recovery.retries"), Const(1)))
    )
    assert isinstance(assign.value.right.value, int)  # integer literals stay integers
    assert [c.target.text for c in rule.calls()] == ["Recovery.recover"]
    assert [n.text for n in rule.variables_written()] == ["Recovery.retries"]


def test_crisp_precedence_not_and_or_arithmetic() -> None:
    rule = parse_rule("if not a > 1 or b != 'x' and c then x = -a * (b + 2) / 3", "crisp")
    assert strip(rule.condition) == strip(
        BoolOp(
            "or",
            Not(Compare(">", var("a"), Const(1.0))),
            BoolOp("and", Compare("!=", var("b"), Const("x")), var("c")),
        )
    )
    (assign,) = rule.actions
    assert strip(assign.value) == strip(
        Arith("/", Arith("*", Neg(var("a")), Arith("+", var("b"), Const(2.0))), Const(3.0))
    )
    assert strip(parse_rule("if a - b - c then x = 1", "crisp").condition) == strip(
        Arith("-", Arith("-", var("a"), var("b")), var("c"))
    )


def test_crisp_constants_and_calls() -> None:
    rule = parse_rule('if TRUE and not False then log("hi there", 1, a.b) and n = 2', "crisp")
    assert strip(rule.condition) == strip(BoolOp("and", Const(True), Not(Const(False))))
    call, _ = rule.actions
    assert strip(call.args) == strip((Const("hi there"), Const(1.0), var("a.b")))


def test_fuzzy_syntax_is_not_crisp_and_back() -> None:
    with pytest.raises(RuleSyntaxError):
        parse_rule("if a is x then b is y", "crisp")
    with pytest.raises(RuleSyntaxError):
        parse_rule("if a == 1 then b = 2", "fuzzy")
    with pytest.raises(ValueError):
        parse_rule("if a is x then b is y", "neural")


# ---------------------------------------------------------------------------------------- errors
@pytest.mark.parametrize(
    ("text", "kind", "column", "fragment"),
    [
        ("if a is then b is y", "fuzzy", 9, "'then'"),
        ("if a is x then b is", "fuzzy", 20, "end of rule"),
        ("if a x then b is y", "fuzzy", 6, "'x'"),
        ("if a is x then b is y $", "fuzzy", 23, "'$'"),
        ("if a is x b is y", "fuzzy", 11, "'b'"),
        ("a is x then b is y", "fuzzy", 3, "'is'"),
        ("if speed == then x = 1", "crisp", 13, "'then'"),
        ("if a then f(1,", "crisp", 15, "end of rule"),
        ("if a then x = 1 +", "crisp", 18, "end of rule"),
    ],
)
def test_error_columns(text: str, kind: str, column: int, fragment: str) -> None:
    with pytest.raises(RuleSyntaxError) as err:
        parse_rule(text, kind)
    assert err.value.column == column, err.value.message
    assert fragment in err.value.message


def test_a_rule_is_one_line() -> None:
    with pytest.raises(RuleSyntaxError) as err:
        parse_rule("if a is x\nthen b is y")
    assert err.value.column == 10 and "one line" in err.value.message


@pytest.mark.parametrize("word", ["if", "then", "and", "or", "not", "is", "with", "IF", "Then"])
def test_keywords_are_not_names(word: str) -> None:
    for text in (
        f"if {word} is x then b is y",  # as a variable
        f"if a is x then {word} is y",  # as an output
        f"{word}: if a is x then b is y",  # as a label
    ):
        with pytest.raises(RuleSyntaxError):
            parse_rule(text)
    with pytest.raises(RuleSyntaxError):
        parse_rule(f"if {word} == 1 then x = 1", "crisp")


def test_names_that_start_with_a_keyword_are_names() -> None:
    rule = parse_rule("iffy: if island is notable and android is orange then within is isolated")
    assert rule.label == "iffy"
    assert [n.text for n in rule.variables_read()] == ["island", "android"]
    assert rule.condition.left.term.text == "notable"
    assert [n.text for n in rule.variables_written()] == ["within"]
    assert parse_rule("if is_on == true then then_x = 1", "crisp").actions[0].var.text == "then_x"


# ----------------------------------------------------------------------------------------- terms
def test_term_lists() -> None:
    terms = parse_terms(
        "a := trape 0 0 1 2; b := TRIAN 1 2 3; c := gauss 1 0.5; d := gbell 1 2 3; "
        "e := sigm 1 2; f := (0, 0) (1, 1) (2, 0); g := 5;"
    )
    assert [(t.name.text, t.shape, t.parameters) for t in terms] == [
        ("a", "trapezoid", (0.0, 0.0, 1.0, 2.0)),
        ("b", "triangle", (1.0, 2.0, 3.0)),
        ("c", "gaussian", (1.0, 0.5)),
        ("d", "bell", (1.0, 2.0, 3.0)),
        ("e", "sigmoid", (1.0, 2.0)),
        ("f", "points", (0.0, 0.0, 1.0, 1.0, 2.0, 0.0)),
        ("g", "singleton", (5.0,)),
    ]
    assert terms[1].name.column == 21
    assert parse_terms("low := trape -1e1 -5 0 +2.5")[0].parameters == (-10.0, -5.0, 0.0, 2.5)
    # a list may span lines (BOUML writes tag values with newlines)
    assert [t.name.text for t in parse_terms("low := trian 0 1 2;\nhigh := trian 1 2 3")] == [
        "low",
        "high",
    ]


@pytest.mark.parametrize(
    ("text", "column"),
    [
        ("low := trape 0 0 1", 19),  # a point missing
        ("low = trape 0 0 1 2", 5),
        ("low := square 0 1", 8),  # an unknown shape is pointed at
        ("low := trian 0 1 2; ; high := trian 1 2 3", 21),
        ("if := trian 0 1 2", 1),
    ],
)
def test_term_list_errors(text: str, column: int) -> None:
    with pytest.raises(RuleSyntaxError) as err:
        parse_terms(text)
    assert err.value.column == column, err.value.message


def test_split_rules() -> None:
    value = "r1: if a is x then b is y\n\n   # a comment\n// another\n  if c is z then b is w  \n"
    lines = split_rules(value)
    assert [(ln.text, ln.line) for ln in lines] == [
        ("r1: if a is x then b is y", 1),
        ("if c is z then b is w", 5),
    ]


# ------------------------------------------------------------------------------------ round trip
# Made once, drawn from many times (a strategy made afresh for each draw is validated afresh).
_FIRST = st.sampled_from("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_")
_REST = st.text("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_0123456789", max_size=6)
_PART = st.builds(lambda f, r: f + r, _FIRST, _REST).filter(lambda s: s.lower() not in KEYWORDS)
_PARTS = {
    dotted: st.lists(_PART, min_size=1, max_size=3 if dotted else 1) for dotted in (False, True)
}


def _ident(draw, dotted: bool = False) -> str:
    return ".".join(draw(_PARTS[dotted]))


names = st.composite(lambda draw: _ident(draw))()
variables = st.composite(lambda draw: _ident(draw, dotted=True))()
case = st.sampled_from([str.lower, str.upper, str.title])


@st.composite
def fuzzy_conditions(draw, depth: int = 0):
    if depth >= 3 or draw(st.integers(0, 2)) == 0:
        hedges = draw(st.lists(st.sampled_from(["not", "very", "somewhat"]), max_size=3))
        return Is(Name(draw(variables), 0), tuple(hedges), Name(draw(names), 0))
    kind = draw(st.sampled_from(["and", "or", "not"]))
    if kind == "not":
        return Not(draw(fuzzy_conditions(depth + 1)))
    return BoolOp(kind, draw(fuzzy_conditions(depth + 1)), draw(fuzzy_conditions(depth + 1)))


@st.composite
def fuzzy_rules(draw):
    condition = draw(fuzzy_conditions())
    actions = tuple(
        Consequent(Name(draw(variables), 0), Name(draw(names), 0))
        for _ in range(draw(st.integers(1, 3)))
    )
    label = draw(st.none() | names)
    weight = draw(st.none() | st.floats(0, 1, allow_nan=False))
    return label, condition, actions, weight


def print_fuzzy(node, level: int, draw) -> str:
    """Text for ``node`` where a construct of at least ``level`` may stand (1: and/or, 2: atom)."""
    kw = draw(case)
    if isinstance(node, Is):
        hedges = "".join(f"{kw(h)} " for h in node.hedges)
        text = f"{node.var.text} {kw('is')} {hedges}{node.term.text}"
        own = 2
    elif isinstance(node, Not):
        text = f"{kw('not')} ({print_fuzzy(node.operand, 1, draw)})"
        own = 2
    else:
        left = print_fuzzy(node.left, 1, draw)
        right = print_fuzzy(node.right, 2, draw)
        text = f"{left} {kw(node.op)} {right}"
        own = 1
    if own < level or draw(st.integers(0, 9)) == 0:  # needed, or redundant, parentheses
        return f"({text})"
    return text


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(fuzzy_rules(), st.data())
def test_fuzzy_round_trip(tree, data) -> None:
    label, condition, actions, weight = tree

    def draw(strategy):
        return data.draw(strategy)

    kw = draw(case)
    text = f"{label}: " if label else ""
    text += f"{kw('if')} {print_fuzzy(condition, 1, draw)} {kw('then')} "
    text += f" {kw('and')} ".join(f"{a.var.text} {kw('is')} {a.term.text}" for a in actions)
    if weight is not None:
        text += f" {kw('with')} {weight!r}"
    rule = parse_rule(text)
    assert rule.label == label
    assert strip(rule.condition) == strip(condition)
    assert strip(rule.actions) == strip(actions)
    assert rule.weight == (1.0 if weight is None else weight)
    assert rule.text == text
    for name in all_names((rule.condition, rule.actions)):  # columns point at the names
        assert text[name.column - 1 : name.column - 1 + len(name.text)] == name.text


# crisp: 1 or, 2 and, 3 not, 4 comparison, 5 + -, 6 * /, 7 unary minus, 8 atoms
_LEVEL = {"or": 1, "and": 2, "+": 5, "-": 5, "*": 6, "/": 6}
strings = st.text(
    st.characters(min_codepoint=32, max_codepoint=126, exclude_characters="\"'"), max_size=8
)


@st.composite
def crisp_expressions(draw, depth: int = 0):
    if depth >= 3 or draw(st.integers(0, 2)) == 0:
        return draw(
            st.one_of(
                st.builds(VarRef, st.builds(Name, variables, st.just(0))),
                st.builds(Const, st.floats(0, 1e6, allow_nan=False)),
                st.builds(Const, strings),
                st.builds(Const, st.booleans()),
            )
        )
    sub = crisp_expressions(depth + 1)
    kind = draw(st.sampled_from(["bool", "not", "cmp", "arith", "neg"]))
    if kind == "bool":
        return BoolOp(draw(st.sampled_from(["and", "or"])), draw(sub), draw(sub))
    if kind == "not":
        return Not(draw(sub))
    if kind == "cmp":
        op = draw(st.sampled_from(["==", "!=", "<", "<=", ">", ">="]))
        return Compare(op, draw(sub), draw(sub))
    if kind == "arith":
        return Arith(draw(st.sampled_from(["+", "-", "*", "/"])), draw(sub), draw(sub))
    return Neg(draw(sub))


def print_crisp(node, level: int, draw) -> str:
    kw = draw(case)
    if isinstance(node, BoolOp):
        own = _LEVEL[node.op]
        text = f"{print_crisp(node.left, own, draw)} {kw(node.op)} {print_crisp(node.right, own + 1, draw)}"
    elif isinstance(node, Not):
        own, text = 3, f"{kw('not')} {print_crisp(node.operand, 3, draw)}"
    elif isinstance(node, Compare):
        own = 4
        text = f"{print_crisp(node.left, 5, draw)} {node.op} {print_crisp(node.right, 5, draw)}"
    elif isinstance(node, Arith):
        own = _LEVEL[node.op]
        text = f"{print_crisp(node.left, own, draw)} {node.op} {print_crisp(node.right, own + 1, draw)}"
    elif isinstance(node, Neg):  # "- 3" with a space: "-3" is the number minus three
        own, text = 7, f"- {print_crisp(node.operand, 7, draw)}"
    elif isinstance(node, VarRef):
        own, text = 8, node.var.text
    elif isinstance(node.value, bool):
        own, text = 8, kw("true" if node.value else "false")
    elif isinstance(node.value, str):
        own, text = 8, f'"{node.value}"' if draw(st.booleans()) else f"'{node.value}'"
    else:
        own, text = 8, repr(node.value)
    if own < level or draw(st.integers(0, 9)) == 0:
        return f"({text})"
    return text


@st.composite
def crisp_actions(draw):
    target = Name(draw(variables), 0)
    if draw(st.booleans()):
        return Assign(target, draw(crisp_expressions(2)))
    return Call(target, tuple(draw(st.lists(crisp_expressions(2), max_size=3))))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(crisp_expressions(), st.lists(crisp_actions(), min_size=1, max_size=3), st.data())
def test_crisp_round_trip(condition, actions, data) -> None:
    def draw(strategy):
        return data.draw(strategy)

    def action_text(action) -> str:
        if isinstance(action, Assign):
            return f"{action.var.text} = {print_crisp(action.value, 5, draw)}"
        args = ", ".join(print_crisp(a, 5, draw) for a in action.args)
        return f"{action.target.text}({args})"

    kw = draw(case)
    text = f"{kw('if')} {print_crisp(condition, 1, draw)} {kw('then')} "
    text += f" {kw('and')} ".join(action_text(a) for a in actions)
    rule = parse_rule(text, "crisp")
    assert strip(rule.condition) == strip(condition)
    assert strip(rule.actions) == strip(tuple(actions))
    for name in all_names((rule.condition, rule.actions)):
        assert text[name.column - 1 : name.column - 1 + len(name.text)] == name.text
    assert [n.text for n in names_in(rule.condition)] == [n.text for n in names_in(condition)]


@settings(max_examples=50, deadline=None)
@given(
    st.lists(
        st.tuples(
            names,
            st.sampled_from(["trape", "trian", "gauss", "gbell", "sigm", "points", "singleton"]),
            st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=8, max_size=8),
        ),
        min_size=1,
        max_size=5,
    ),
    st.booleans(),
)
def test_terms_round_trip(spec, trailing) -> None:
    arity = {"trape": 4, "trian": 3, "gauss": 2, "gbell": 3, "sigm": 2, "singleton": 1}
    shape = {
        "trape": "trapezoid",
        "trian": "triangle",
        "gauss": "gaussian",
        "gbell": "bell",
        "sigm": "sigmoid",
        "points": "points",
        "singleton": "singleton",
    }
    parts, expected = [], []
    for name, kind, numbers in spec:
        if kind == "points":
            params = tuple(numbers[:6])
            body = " ".join(f"({params[i]!r}, {params[i + 1]!r})" for i in range(0, 6, 2))
        else:
            params = tuple(numbers[: arity[kind]])
            body = " ".join(repr(x) for x in params)
            if kind != "singleton":
                body = f"{kind} {body}"
        parts.append(f"{name} := {body}")
        expected.append(TermDef(Name(name, 0), shape[kind], params))
    text = "; ".join(parts) + (";" if trailing else "")
    terms = parse_terms(text)
    assert strip(terms) == strip(expected)
    for term in terms:
        assert text[term.name.column - 1 :].startswith(term.name.text + " :=")
