"""Whatever a model names things, no generated path leaves the output directory and no generated
file says more than the model did: names that cannot be file names are refused (G701), paths
that would be one file on some system are refused (G702), names that are not identifiers never
reach an FCL or CLIPS file (G703), and comment headers cannot be broken out of."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import clips
import pytest

from acordcs.descriptor import Application
from acordcs.engines.fuzzy import read_fcl
from acordcs.generator import target
from acordcs.generator.errors import BuildError
from acordcs.generator.paths import case_collisions, path_problem, segment_problem
from acordcs.generator.targets.rule_files import rules
from tests.support.generator import build, context, registered, snapshot, weblab_variant
from tests.support.toolchain import WEBLAB, no_crash

r = dataclasses.replace


@pytest.mark.parametrize(
    "name",
    ["../../x", "/tmp/absolute", "a\\b", "..", "CON", "nul.txt", "x.", "a:b", 'q"'],
)
def test_model_names_that_cannot_be_file_names_are_refused(tmp_path: Path, name: str):
    quoted = name.replace("&", "&amp;").replace('"', "&quot;")
    model = weblab_variant(tmp_path, ('name="WebLab">', f'name="{quoted}">'))
    out = tmp_path / "deep" / "er" / "out"
    before = snapshot(tmp_path)
    result = build(model, out)
    no_crash(result)
    assert result.code == 1, result.both
    assert ": error: G701 the name " in result.out and "rename it" in result.out
    assert snapshot(tmp_path) == before  # nothing written anywhere, out not even created


def test_names_differing_only_in_case_are_refused(tmp_path: Path):
    model = weblab_variant(tmp_path, ('name="BandwidthLimiting"', 'name="speedLimiting"'))
    out = tmp_path / "out"
    result = build(model, out)
    assert result.code == 1, result.both
    # The model check sees it before any file name is made (N606); the writer's own guard against
    # files differing only in case (G702) is held below, with a target that makes such files.
    assert (
        "error: N606 ACORD-CS elements 'SpeedLimiting', 'speedLimiting' differ only" in result.out
    )
    assert "WebLab::ContextAwareNavigation::Adaptation::speedLimiting" in result.out
    assert not out.exists()


@pytest.mark.parametrize(
    "path",
    [
        "../x.txt",
        "/abs.txt",
        "a/\x00.txt",
        ".acordcs-manifest.json",
        "a/../b.txt",
        "C:x.txt",
        "a//b",
        "d/",
    ],
)
def test_a_target_cannot_write_outside_the_output(tmp_path: Path, path: str):
    @target("escape", description="writes where it should not")
    def escape(context) -> None:
        context.emit(path, "x", element="WebLab")

    out = tmp_path / "a" / "out"
    with registered(escape):
        result = build(WEBLAB, out, "--target", "escape")
    no_crash(result)
    assert result.code == 1
    assert "error: G701 target escape would write" in result.out
    assert not (tmp_path / "a").exists() and not Path("/abs.txt").exists()


def test_two_files_that_would_be_one_are_refused(tmp_path: Path):
    @target("twice", description="one file twice, two differing in case")
    def twice(context) -> None:
        context.emit("rules/SpeedLimiting.fcl", "x", element="A")
        context.emit("a/Readme.txt", "x", element="B")
        context.emit("A/README.txt", "y", element="C")

    with registered(twice):
        result = build(WEBLAB, tmp_path / "out")
    assert result.code == 1
    assert "G702 targets rules and twice would both write 'rules/SpeedLimiting.fcl'" in result.out
    assert "G702 'A/README.txt' and 'a/Readme.txt' differ only in case" in result.out
    assert not (tmp_path / "out").exists()


def test_path_rules():
    assert path_problem("rules/SpeedLimiting.fcl") is None
    assert path_problem("Web Lab #1 %20 é.descriptor.xml") is None
    assert "absolute" in path_problem("/etc/passwd")
    assert "device name" in segment_problem("com1.fcl")
    assert "U+0000" in segment_problem("a\x00b")
    assert "U+000A" in segment_problem("a\nb")
    assert case_collisions(["a/B", "a/b", "c"]) == [("a/B", "a/b")]
    assert case_collisions(["Straße", "STRASSE"]) == [("STRASSE", "Straße")]


NASTY = [
    'x"y',
    "a\nb",
    "x) (defrule MAIN::evil => (halt)",
    "END_FUNCTION_BLOCK FUNCTION_BLOCK evil",
    "a b",
    "1x",
    "",
    "é",
    "a.b",
    "(*",
]


def _fuzzy(app: Application):
    return next(ps for ps in app.policy_sets if ps.name == "SpeedLimiting")


def _crisp(app: Application):
    return next(ps for ps in app.policy_sets if ps.name == "Recovering")


def _with_set(app: Application, ps) -> Application:
    return r(app, policy_sets=tuple(ps if p.id == ps.id else p for p in app.policy_sets))


def _rename_element(ps, old: str, new: str):
    """``ps`` with element ``old`` renamed ``new`` wherever its bindings name it."""

    def renamed(name: str) -> str:
        return new + name[len(old) :] if name.startswith(old + ".") else name

    return r(
        ps,
        bound=tuple(r(b, element=new) if b.element == old else b for b in ps.bound),
        inputs=tuple(map(renamed, ps.inputs)),
        outputs=tuple(map(renamed, ps.outputs)),
        triggers=tuple(map(renamed, ps.triggers)),
    )


def _mutations(app: Application, nasty: str) -> dict[str, Application]:
    fuzzy, crisp = _fuzzy(app), _crisp(app)
    policy = fuzzy.policies[0]
    variable = fuzzy.variables[0]
    return {
        "fuzzy set name": _with_set(app, r(fuzzy, name=nasty)),
        "policy name": _with_set(
            app, r(fuzzy, policies=(r(policy, name=nasty), *fuzzy.policies[1:]))
        ),
        "rule label": _with_set(
            app,
            r(
                fuzzy,
                policies=(r(policy, rules=(r(policy.rules[0], label=nasty), *policy.rules[1:])),),
            ),
        ),
        "term name": _with_set(
            app,
            r(
                fuzzy,
                variables=(
                    r(variable, terms=(r(variable.terms[0], name=nasty), *variable.terms[1:])),
                    *fuzzy.variables[1:],
                ),
            ),
        ),
        "variable attribute": _with_set(
            app, r(fuzzy, variables=(r(variable, attribute=nasty), *fuzzy.variables[1:]))
        ),
        "crisp policy name": _with_set(app, r(crisp, policies=(r(crisp.policies[0], name=nasty),))),
        # What the rules name reaches the files as the descriptor bound it.
        "bound attribute": _with_set(
            app, r(fuzzy, bound=(r(fuzzy.bound[0], member=nasty), *fuzzy.bound[1:]))
        ),
        "bound element": _with_set(app, _rename_element(crisp, crisp.bound[0].element, nasty)),
        "bound operation": _with_set(
            app,
            r(
                crisp,
                bound=tuple(
                    r(b, member=nasty) if b.kind == "operation" else b for b in crisp.bound
                ),
            ),
        ),
    }


@pytest.mark.parametrize("nasty", NASTY, ids=repr)
def test_names_that_are_not_identifiers_never_reach_rule_files(
    weblab: Application, tmp_path: Path, nasty: str
):
    for field, app in _mutations(weblab, nasty).items():
        if field == "bound element" and nasty == "a.b":
            continue  # an element named A.b is how a port is named: a.b.x is a variable name
        ctx = context(app, tmp_path)
        with pytest.raises(BuildError) as caught:
            rules(ctx)
        (found,) = caught.value.diagnostics
        assert found.code == "G703", field
        assert "is not an identifier" in found.message and "rename it" in found.message, field
        # the files of the sets before it are dropped by the build with the error
        assert all(f.path.endswith((".fcl", ".clp")) for f in ctx.files)


HEADER_ATTACK = "X *) FUNCTION_BLOCK evil (* \n(defrule MAIN::evil => (halt))\n; --> <!-- "


def test_headers_cannot_be_broken_out_of(weblab: Application, tmp_path: Path):
    fuzzy, crisp = _fuzzy(weblab), _crisp(weblab)
    app = _with_set(
        _with_set(weblab, r(fuzzy, qualified_name=HEADER_ATTACK, id=HEADER_ATTACK)),
        r(crisp, qualified_name=HEADER_ATTACK),
    )
    ctx = context(app, tmp_path, source=f"evil{HEADER_ATTACK}.xmi")
    rules(ctx)
    files = {f.path: f.data.decode() for f in ctx.files}
    fcl = files["rules/SpeedLimiting.fcl"]
    assert list(read_fcl(fcl)) == ["SpeedLimiting"]  # one block: the header stayed a comment
    assert fcl.splitlines()[1].startswith("   in model file evil")
    env = clips.Environment()
    path = tmp_path / "Recovering.clp"
    path.write_text(files["rules/Recovering.clp"], encoding="utf-8")
    env.load(str(path))
    assert not any("evil" in str(n) for n in env.eval("(get-defrule-list *)"))
    assert all(line.startswith(";") for line in files["rules/Recovering.clp"].splitlines()[:5])


def test_a_name_too_long_for_a_file_system_is_refused(tmp_path: Path):
    model = weblab_variant(tmp_path, ('name="WebLab">', f'name="{"W" * 250}">'))
    result = build(model, tmp_path / "out")
    assert result.code == 1
    assert "it is longer than 200 bytes (file systems allow 255, to leave room" in result.out


def test_target_names_are_words():
    with pytest.raises(ValueError, match="cannot name a target"):
        target("a,b")(lambda context: None)
    with pytest.raises(ValueError, match="cannot name a target"):
        target("all")(lambda context: None)
