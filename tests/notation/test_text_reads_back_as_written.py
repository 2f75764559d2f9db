"""Whatever the text writer writes, the reader reads back as it was: names and values of any
characters (quoted and escaped where needed, keywords as names), comments, ids, blocks; and the
fast reader and lark's parser agree on it. Drawn by hypothesis."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.notation import outline as o
from acordcs.notation.fast_text import read_outline
from acordcs.notation.syntax import MAX_DEPTH, lark_outline, parse_text
from acordcs.notation.text_form import text_of

# Any character but a lone surrogate (not text) and NUL, which the reader refuses.
ANY = st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"), max_size=10)
KEYWORDS = st.sampled_from(
    ["model", "package", "id", "in", "out", "rules", "port", "hosts", "variable", "attribute"]
)
NAMES = ANY | KEYWORDS | st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,8}", fullmatch=True)
DOC = st.lists(ANY.map(lambda t: t.replace("\n", " ").rstrip("\r")), max_size=2)
LINE = st.from_regex(r"[a-z][a-z0-9 :=.<>()*+-]{0,30}[a-z0-9)]", fullmatch=True)
IDS = st.none() | ANY
VALUES = ANY | st.from_regex(r"[+-]?\d{1,4}(\.\d{1,3})?", fullmatch=True)

tags = st.lists(st.builds(o.Tag, NAMES, VALUES), max_size=3)
parameters = st.lists(
    st.builds(o.Parameter, NAMES, st.none() | NAMES, st.sampled_from(["in", "out", "inout"]), IDS),
    max_size=3,
)
variables = st.none() | st.builds(
    o.Variable,
    tags,
    st.none() | st.builds(o.Block, st.lists(st.tuples(LINE, st.just(o.Place())), max_size=3)),
)
attributes = st.builds(
    o.Attribute, NAMES, st.none() | NAMES, st.none() | VALUES, variables, DOC, IDS
)
operations = st.builds(o.Operation, NAMES, parameters, st.none() | NAMES, DOC, IDS)
relations = st.builds(
    o.Relation,
    st.sampled_from(list(o.RELATIONS)),
    st.lists(
        st.tuples(st.lists(NAMES, min_size=1, max_size=3).map(tuple), st.just(o.Place())),
        min_size=1,
        max_size=3,
    ),
)
rules = st.lists(
    st.tuples(
        st.sampled_from(["Rule", "RuleSlowDown"]),
        st.builds(o.Block, st.lists(st.tuples(LINE, st.just(o.Place())), max_size=3)),
    ),
    max_size=2,
)
elements = st.builds(
    o.Element,
    st.sampled_from(list(o.KINDS)),
    NAMES,
    tags,
    rules,
    st.lists(attributes, max_size=2),
    st.lists(operations, max_size=2),
    st.lists(relations, max_size=2),
    st.just([]),
    DOC,
    IDS,
)
items = st.recursive(
    elements,
    lambda inner: st.builds(o.Package, NAMES, st.lists(inner, max_size=3), DOC, IDS),
    max_leaves=6,
)
outlines = st.builds(o.Outline, NAMES, st.lists(items, max_size=3), DOC, IDS)


@settings(max_examples=40, deadline=None)  # each draw is a whole model
@given(outlines)
def test_the_text_of_an_outline_reads_back_as_the_same_text(outline: o.Outline) -> None:
    text = text_of(outline)
    read = parse_text(text.encode("utf-8"))
    assert text_of(read) == text
    assert read.name == outline.name and read.doc == outline.doc and read.id == outline.id
    assert [i.name for i in read.items] == [i.name for i in outline.items]
    fast = read_outline(text, MAX_DEPTH)
    assert fast is not None and fast == lark_outline(text)
