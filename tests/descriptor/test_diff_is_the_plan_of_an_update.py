"""The difference between two descriptors is the plan of an update (``acordcs.descriptor.diff``):
one line per change, ``+``/``-``/``~``, the element and what changes. Checked on both samples with
edits drawn by hypothesis: each single edit gives exactly the one change it makes (and an element
added is the reverse of it removed), a descriptor compared with itself gives none, an element moved
to another container cannot apply live; the issue's example line, word for word."""

from __future__ import annotations

from dataclasses import replace
from functools import cache

from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.descriptor.application import Application
from acordcs.descriptor.diff import diff, elided, shown
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from tests.support.generator import weblab_variant
from tests.support.toolchain import SMARTROOM, WEBLAB

SETTINGS = settings(max_examples=30, deadline=None)
KINDS = ("components", "connections", "monitors", "policy_sets")
LABEL = {
    "components": "component",
    "connections": "connection",
    "monitors": "monitor",
    "policy_sets": "policy set",
}


@cache
def sample(path) -> Application:
    return describe(read_model(str(path)).architecture)


samples = st.sampled_from([WEBLAB, SMARTROOM]).map(sample)


def test_the_issues_example_line(tmp_path):
    edited = weblab_variant(
        tmp_path,
        (
            "angle is narrow then Locomotion.maxSpeed is slow&#10;smallMedium",
            "angle is narrow then Locomotion.maxSpeed is fast&#10;smallMedium",
            2,
        ),
    )
    plan = diff(sample(WEBLAB), describe(read_model(str(edited)).architecture))
    assert plan.lines == (
        "~ policy set SpeedLimiting: rule smallNarrow: ... is slow -> ... is fast",
    )
    (change,) = plan.changes
    assert change.live and change.action == "replan" and change.containers == ("WebLabSide",)
    assert plan.part("WebLabSide") == plan.changes and plan.part("UserSide") == ()


@given(samples)
@SETTINGS
def test_a_descriptor_against_itself_plans_nothing(app):
    assert not diff(app, app) and diff(app, app).live


@given(samples, st.data())
@SETTINGS
def test_a_rule_rewritten_is_one_change_of_its_set(app, data):
    ps = data.draw(st.sampled_from(app.policy_sets))
    p = data.draw(st.sampled_from([p for p in ps.policies if p.rules]))
    i = data.draw(st.integers(0, len(p.rules) - 1))
    rule = p.rules[i]
    text = rule.text + " and " + rule.text.split(" then ", 1)[1]
    rules = (*p.rules[:i], replace(rule, text=text), *p.rules[i + 1 :])
    policies = tuple(replace(q, rules=rules) if q is p else q for q in ps.policies)
    edited = replace(app, policy_sets=_swap(app.policy_sets, replace(ps, policies=policies)))
    (change,) = diff(app, edited).changes
    assert change.line.startswith(f"~ policy set {ps.name}: rule ")
    assert f"{rule.label}: " in change.line and change.action == "replan" and change.live


@given(samples, st.data())
@SETTINGS
def test_a_default_changed_is_one_change_naming_both_values(app, data):
    owners = [c for c in app.components if c.properties]
    comp = data.draw(st.sampled_from(owners))
    prop = data.draw(st.sampled_from(comp.properties))
    value = {
        "int": st.integers(-1000, 1000),
        "double": st.floats(-1e6, 1e6, allow_nan=False),
        "bool": st.booleans(),
        "string": st.text(max_size=8),
    }[prop.kind]
    new = data.draw(value.filter(lambda v: v != prop.default))
    props = tuple(replace(p, default=new) if p is prop else p for p in comp.properties)
    edited = replace(app, components=_swap(app.components, replace(comp, properties=props)))
    (change,) = diff(app, edited).changes
    assert change.line == (
        f"~ component {comp.name}: property {prop.name}: default {shown(prop.default)} -> {shown(new)}"
    )
    assert (change.action, change.target, change.attribute) == ("default", comp.name, prop.name)
    assert (change.old, change.value) == (prop.default, new)


@given(samples, st.data())
@SETTINGS
def test_an_element_removed_is_the_reverse_of_it_added(app, data):
    kind = data.draw(st.sampled_from([k for k in KINDS if getattr(app, k)]))
    item = data.draw(st.sampled_from(getattr(app, kind)))
    less = replace(app, **{kind: tuple(x for x in getattr(app, kind) if x is not item)})
    gone, *fed = diff(app, less).changes
    assert gone.line == f"- {LABEL[kind]} {item.name}" and gone.live
    back, *fed_again = diff(less, app).changes
    assert back.line.startswith(f"+ {LABEL[kind]} {item.name}") and back.live
    assert back.action == "add" and gone.action == "remove"
    # a monitor's policy sets are no longer fed by it, then fed again
    feeds = sorted(f.name for f in getattr(item, "feeds", ()))
    assert sorted(c.element for c in fed) == sorted(c.element for c in fed_again) == feeds
    assert all(" fed by " in f" {c.what}" and c.action == "replan" for c in fed + fed_again)


def test_an_element_moved_to_another_container_cannot_apply_live():
    app = sample(WEBLAB)
    user, lab = app.containers
    vision = next(r for r in lab.hosts if r.name == "Vision")
    moved = replace(
        app,
        containers=(
            replace(user, hosts=(*user.hosts, vision)),
            replace(lab, hosts=tuple(r for r in lab.hosts if r is not vision)),
        ),
    )
    plan = diff(app, moved)
    assert plan.lines == ("~ component Vision: container WebLabSide -> UserSide",)
    assert not plan.live and "stop and start" in plan.changes[0].why
    assert plan.part("UserSide") == plan.part("WebLabSide") == plan.changes


WORDS = st.lists(st.sampled_from(["if", "x", "is", "slow", "fast", "and", "y", "then"]), min_size=1)


@given(WORDS, WORDS)
@SETTINGS
def test_elision_leaves_out_only_words_both_sides_share(a, b):
    old, new = " ".join(a), " ".join(b)
    left, right = elided(old, new).split(" -> ")
    for side, text in ((left, old), (right, new)):
        core = side.removeprefix("... ").removesuffix(" ...")
        assert core in text  # what is shown is the text's own words, in order
        if side.startswith("... "):
            assert text.startswith(tuple(_heads(old, new)))
    if old != new:
        assert left != right


def _heads(old: str, new: str):
    """Prefixes both texts share (an elided start stands for one)."""
    a, b = old.split(" "), new.split(" ")
    n = 0
    while n < min(len(a), len(b)) and a[n] == b[n]:
        n += 1
    return [" ".join(a[:k]) for k in range(1, n + 1)]


def _swap(items: tuple, new) -> tuple:
    return tuple(new if x.name == new.name else x for x in items)
