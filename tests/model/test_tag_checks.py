"""The tag checks (acordcs.model.checks.tags): unknown tags, tag values in their XSD lexical form,
term lists judged against each variable's own range, and term shapes accepted exactly when the fuzzy
engine accepts them."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.engines.fuzzy.membership import make_membership
from acordcs.engines.rule_engine import RuleError
from acordcs.model.checks.tags import shape_problem
from acordcs.rules import Name, TermDef
from tests.support.toolchain import codes_in, rule_and_tag_findings, run_main, write_model


def test_an_unknown_plain_tag_on_an_acordcs_element_is_reported(weblab_text, tmp_path):
    text = weblab_text.replace(
        '<stereotype name="ACORDCS:CtxMonitor"/>',
        '<stereotype name="ACORDCS:CtxMonitor"/><taggedValue tag="colour" value="red"/>',
        1,  # the first monitor only
    )
    result = run_main(["validate", str(write_model(tmp_path, text))])
    assert codes_in(result.out) == {"T303"} and "'colour'" in result.out
    assert result.code == 0  # a warning: a tag of another tool's, perhaps
    assert (
        run_main(["validate", "--fail-on", "warning", str(write_model(tmp_path, text))]).code == 1
    )


def test_a_tag_two_edits_from_a_known_one_is_a_misspelling_and_an_error(weblab_text, tmp_path):
    for typo in ("frequncy", "frequenccy", "Frequency", "fr3quncy"):
        text = weblab_text.replace(
            '<stereotype name="ACORDCS:CtxMonitor"/>',
            f'<stereotype name="ACORDCS:CtxMonitor"/><taggedValue tag="{typo}" value="2"/>',
            1,
        )
        result = run_main(["validate", str(write_model(tmp_path, text))])
        assert codes_in(result.out) == {"T320"}, (typo, result.out)
        assert f"has no tag '{typo}' (did you mean 'frequency'?)" in result.out
        assert result.code == 1
    far = weblab_text.replace(
        '<stereotype name="ACORDCS:CtxMonitor"/>',
        '<stereotype name="ACORDCS:CtxMonitor"/><taggedValue tag="frqncyy" value="2"/>',
        1,
    )
    assert codes_in(run_main(["validate", str(write_model(tmp_path, far))]).out) == {"T303"}


def test_tag_numbers_use_the_xsd_lexical_form(weblab_text, tmp_path):
    text = weblab_text.replace('frequency="1" base_Element', 'frequency="1_0" base_Element')
    text = text.replace('CtxMonitor:frequency" value="1"', 'CtxMonitor:frequency" value="1_0"')
    result = run_main(["validate", str(write_model(tmp_path, text))])
    assert "T304" in codes_in(result.out), result.out


# ------------------------------------------------------------------------------------ term lists
def test_shared_term_lists_are_judged_against_each_range(tmp_path) -> None:
    terms = "lo := trape 10 10 20 40; mid := trian 20 40 60; lo := trian 50 60 70"
    bad = "a := trian 3 2 1; b := gauss 1 0"

    def build(gen, pkg):
        c = gen.ctx(pkg.cls("Comp"), "CtxComponent")
        for name, lo, hi in (
            ("v1", "0", "100"),
            ("v2", "-0", "100"),
            ("v3", "0", "50"),
            ("v4", "0", "50"),
        ):
            c.attr(name, "double", stereotype="ACORDCS:CtxVariable",
                   tags=gen.stereotype_tags("CtxVariable", min=lo, max=hi, terms=terms))  # fmt: skip
        for name in ("w1", "w2"):
            c.attr(name, "double", stereotype="ACORDCS:CtxVariable",
                   tags=gen.stereotype_tags("CtxVariable", min="0", max="1", terms=bad))  # fmt: skip

    found = rule_and_tag_findings(tmp_path, build)
    twice = [("T312", "term 'lo' is defined twice")]
    wanted = [
        *twice,
        (
            "T309",
            "no term of 'v1' covers [0, 10] of its range [0, 100]: an input there fires no rule",
        ),
        *twice,
        (
            "T309",
            "no term of 'v2' covers [-0, 10] of its range [-0, 100]: an input there fires no rule",
        ),
        *twice,
        ("T308", "term 'mid' has point 60 outside the range [0, 50]"),
        ("T308", "term 'lo' has point 60 outside the range [0, 50]"),
        (
            "T309",
            "no term of 'v3' covers [0, 10] of its range [0, 50]: an input there fires no rule",
        ),
        *twice,
        ("T308", "term 'mid' has point 60 outside the range [0, 50]"),
        ("T308", "term 'lo' has point 60 outside the range [0, 50]"),
        (
            "T309",
            "no term of 'v4' covers [0, 10] of its range [0, 50]: an input there fires no rule",
        ),
        ("T311", "term 'a': points 3 2 1 must not decrease"),
        ("T311", "term 'b': the standard deviation must be positive"),
        ("T311", "term 'a': points 3 2 1 must not decrease"),
        ("T311", "term 'b': the standard deviation must be positive"),
    ]
    assert sorted(found) == sorted(wanted)


NUMBERS = st.one_of(
    st.floats(min_value=-100, max_value=100, allow_nan=False),
    st.sampled_from([0.0, 1.0, float("inf"), float("nan")]),
)
SHAPES = {"trapezoid": 4, "triangle": 3, "gaussian": 2, "bell": 3, "sigmoid": 2, "singleton": 1}


@st.composite
def term_defs(draw):
    shape = draw(st.sampled_from([*SHAPES, "points"]))
    if shape == "points":
        xs = sorted(draw(st.lists(st.sampled_from([0.0, 1.0, 2.0, 3.0]), min_size=2, max_size=5)))
        ys = draw(
            st.lists(st.sampled_from([0.0, 0.5, 1.0, 1.5]), min_size=len(xs), max_size=len(xs))
        )
        params = tuple(v for pair in zip(xs, ys, strict=True) for v in pair)
    else:
        params = tuple(draw(st.lists(NUMBERS, min_size=SHAPES[shape], max_size=SHAPES[shape])))
    return TermDef(Name("t", 1), shape, params)


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(term_defs())
def test_the_validator_accepts_exactly_the_terms_the_fuzzy_engine_accepts(term):
    try:
        make_membership(term.shape, term.parameters)
        engine_ok = True
    except RuleError:
        engine_ok = False
    assert (shape_problem(term) is None) == engine_ok, (term, shape_problem(term))
