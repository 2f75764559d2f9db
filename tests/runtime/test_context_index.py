"""The subscription index against lxml as the oracle: same matches, same nodes, in the same order."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from acordcs.runtime.context import SubscriptionIndex
from acordcs.runtime.context.xpathexpr import compile_expression, recognise
from acordcs.runtime.context.xpathnum import xpath_number

# strings whose XPath number() is easy to get wrong
TRICKY = [
    "1e3",
    " 5 ",
    ".5",
    "-0",
    "0",
    "Infinity",
    "NaN",
    "5",
    "10",
    "-3.5",
    "abc",
    "",
    "1E3",
    "\t7\n",
    "5.",
    "+5",
    "0.1",
    "00.30",
    "1e-2",
    "-.5",
    "123456789012345678901234567890",
    "0.30000000000000004",
    "2.675",
    "1 2",
    "\u00a05",
    "-",
    ".",
    "1e",
    "9007199254740993",
]
NAMES = ["a", "b", "c"]
OPS = ["=", "!=", "<", "<=", ">", ">="]
NUM_LITERALS = [
    "5",
    "10",
    "0",
    "-0",
    ".5",
    "5.",
    "1e3",
    "0.1",
    "0.30",
    "-3.5",
    "3",
    "7",
    "1e-2",
    "2.675",
]


@st.composite
def documents(draw: st.DrawFn, depth: int = 0) -> etree._Element:
    name = draw(st.sampled_from([*NAMES, "{urn:x}a"] if depth else NAMES))
    elem = etree.Element(name)
    if draw(st.booleans()):
        elem.set(draw(st.sampled_from(["x", "y"])), draw(st.sampled_from(TRICKY)))
    elem.text = draw(st.sampled_from([None, *TRICKY]))
    if depth < 3:
        for _ in range(draw(st.integers(0, 3))):
            kind = draw(st.integers(0, 9))
            if kind == 0:
                child = etree.Comment(draw(st.sampled_from(["c", "5"])))
            elif kind == 1:
                child = etree.ProcessingInstruction("pi", "7")
            else:
                child = draw(documents(depth + 1))
            child.tail = draw(st.sampled_from([None, None, "1", " "]))
            elem.append(child)
    return elem


@st.composite
def expressions(draw: st.DrawFn) -> str:
    steps = draw(st.lists(st.sampled_from([*NAMES, "*"]), min_size=1, max_size=3))
    seps = [draw(st.sampled_from(["/", "/", "//"])) for _ in steps]
    path = "".join(s + n for s, n in zip(seps, steps, strict=True))
    if draw(st.integers(0, 4)) == 0:
        path += draw(st.sampled_from(["/@x", "//@y"]))
    shape = draw(st.integers(0, 9))
    if shape == 0:
        return path
    if shape == 1:
        return draw(
            st.sampled_from(
                [
                    "count(//a)",
                    "//a[2]",
                    "boolean(//b)",
                    "string(/a)",
                    "//a[b and c]",
                    "/a/text()",
                    "sum(//@x)",
                ]
            )
        )
    value = draw(st.sampled_from([".", ".", *NAMES, "@x", "@y"]))
    op = draw(st.sampled_from(OPS))
    if draw(st.booleans()):
        const = draw(st.sampled_from(NUM_LITERALS))
    else:
        const = "'" + draw(st.sampled_from([t for t in TRICKY if "'" not in t])) + "'"
    space = draw(st.sampled_from(["", " "]))
    pred = (
        f"{value}{space}{op}{space}{const}"
        if draw(st.booleans())
        else f"{const}{space}{op}{space}{value}"
    )
    return f"{path}[{pred}]"


class Sub:
    def __init__(self, expr: str, publisher: str | None) -> None:
        self.xpath, self.publisher = expr, publisher


def _norm(node: object, tree: etree._ElementTree) -> object:
    # getpath() names a node uniquely and, unlike id(), survives lxml recreating proxies
    if isinstance(node, etree._Element):
        return ("node", tree.getpath(node))
    if isinstance(node, str) and hasattr(node, "getparent") and node.getparent() is not None:
        return ("str", str(node), tree.getpath(node.getparent()), node.attrname, node.is_attribute)
    return ("value", node if not (isinstance(node, float) and math.isnan(node)) else "nan")


def _oracle(sub: Sub, tree: etree._ElementTree, publisher: str) -> list | None:
    if sub.publisher is not None and sub.publisher != publisher:
        return None
    if sub.xpath is None:
        return [_norm(tree.getroot(), tree)]
    # lxml decides whether it matches (XPath boolean()) and what it selects
    if not etree.XPath(f"boolean({sub.xpath})")(tree):
        return None
    value = etree.XPath(sub.xpath)(tree)
    return [_norm(n, tree) for n in value] if isinstance(value, list) else []


def _matches(index: SubscriptionIndex, tree: etree._ElementTree) -> dict[int, list]:
    got: dict[int, list] = {}
    for chunk, nodes, _ in index.match(tree, "p1"):
        for sub in chunk:
            assert id(sub) not in got, "a subscription matched twice"
            got[id(sub)] = [_norm(n, tree) for n in nodes]
    return got


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    doc=documents(),
    subs=st.lists(
        st.tuples(st.one_of(st.none(), expressions()), st.sampled_from([None, "p1", "p2"])),
        min_size=1,
        max_size=25,
    ),
)
def test_index_matches_lxml_exactly(doc: etree._Element, subs: list) -> None:
    tree = etree.ElementTree(doc)
    index = SubscriptionIndex()
    entries = []
    for expr, publisher in subs:
        sub = Sub(expr, publisher)
        compiled = compile_expression(expr, 4096) if expr is not None else None
        form = recognise(expr) if expr is not None else None
        index.add(sub, publisher, form, compiled)
        entries.append((sub, form))
    got = _matches(index, tree)
    for sub, _ in entries:
        expected = _oracle(sub, tree, "p1")
        assert got.get(id(sub)) == expected, (sub.xpath, sub.publisher, etree.tostring(doc))
    # removing half of them leaves the other half intact
    for sub, form in entries[::2]:
        index.remove(sub, sub.publisher, form)
    got = _matches(index, tree)
    for sub, _ in entries[1::2]:
        assert got.get(id(sub)) == _oracle(sub, tree, "p1")
    assert not any(id(sub) in got for sub, _ in entries[::2])


def test_generated_expressions_are_mostly_indexed() -> None:
    # the property test would prove little if everything fell back to lxml
    samples = [
        "/a/b[. > 5]",
        "//a[@x = '1e3']",
        "/a/*[c <= -0]",
        "/a/@x[. != .5]",
        "/a[1e3 < .]",
        "/a/b",
    ]
    assert all(recognise(s) is not None for s in samples)
    assert recognise("//a[2]") is None and recognise("count(//a)") is None
    assert recognise("/a/b[. > 5]").child_steps == ("a", "b")


@pytest.mark.parametrize(
    "text", [*TRICKY, "1e400", "-1e-400", "0e999999", "0." + "0" * 400 + "1", "1" * 400]
)
def test_xpath_number_agrees_with_lxml(text: str) -> None:
    expected = etree.XPath("number($v)")(etree.ElementTree(etree.Element("r")), v=text)
    got = xpath_number(text)
    assert (math.isnan(got) and math.isnan(expected)) or (
        got == expected and math.copysign(1, got) == math.copysign(1, expected)
    )


@settings(max_examples=2000, deadline=None)
@given(st.one_of(st.text(alphabet="0123456789.-eE+ \t\nx", max_size=30), st.floats().map(repr)))
def test_xpath_number_property(text: str) -> None:
    expected = etree.XPath("number($v)")(etree.ElementTree(etree.Element("r")), v=text)
    got = xpath_number(text)
    assert (math.isnan(got) and math.isnan(expected)) or (
        got == expected and math.copysign(1, got) == math.copysign(1, expected)
    )
