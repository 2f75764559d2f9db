"""ClipsEngine: the paper's recovery policy, native rules, replacement by label, callbacks, bad input."""

from __future__ import annotations

import logging
import math

import pytest

from acordcs.engines.clips import ClipsEngine
from acordcs.engines.rule_engine import RuleEngine, RuleError
from acordcs.metamodel import create
from tests.support.ecore_clips_engine import engine_for_policy_set

RECOVERY = [
    "count: if Control.speed == 0 then Recovery.zeros = Recovery.zeros + 1",
    "retry: if Control.speed == 0 and Recovery.zeros <= 3 then Recovery.recover()",
    "giveup: if Control.speed == 0 and Recovery.zeros == 4 then Recovery.askUser()",
    "reset: if Control.speed > 0 then Recovery.zeros = 0",
]


class Recovery:
    def __init__(self) -> None:
        self.log: list[str] = []

    def recover(self) -> None:
        self.log.append("recover")

    def askUser(self) -> None:
        self.log.append("ask")


def recovery_engine() -> tuple[ClipsEngine, Recovery]:
    engine = ClipsEngine()
    engine.declare("Control.speed", 0.0, type="double")
    engine.declare("Recovery.zeros", 0, type="int")
    for rule in RECOVERY:
        engine.defrule(rule, "recovery")
    component = Recovery()
    engine.bind("Recovery", component)
    return engine, component


def test_is_a_rule_engine():
    assert isinstance(ClipsEngine(), RuleEngine)


def test_paper_recovery_policy_three_tries_then_the_user():
    engine, component = recovery_engine()
    seen = []
    for speed in [0, 0, 0, 0, 0, 120, 0, 80.5]:
        engine.set("Control.speed", speed)
        engine.fire("recovery")
        seen.append((tuple(component.log), engine.get("Recovery.zeros")))
        component.log.clear()
    assert seen == [
        (("recover",), 1.0),
        (("recover",), 2.0),
        (("recover",), 3.0),
        (("ask",), 4.0),
        ((), 5.0),
        ((), 0.0),
        (("recover",), 1.0),
        ((), 0.0),
    ]
    assert engine.error_count == 0


def test_a_rule_fires_once_per_fire_even_when_it_changes_what_it_reads():
    engine = ClipsEngine()
    engine.declare("A.n", 0)
    engine.defrule("inc: if A.n >= 0 then A.n = A.n + 1", "s")
    for expected in (1, 2, 3):
        engine.fire("s")
        assert engine.get("A.n") == expected


def test_rules_chain_to_quiescence_in_definition_order():
    engine = ClipsEngine()
    for name in ("A.a", "A.b", "A.c"):
        engine.declare(name, 0)
    engine.defrule("third: if A.b == 1 then A.c = A.a * 10", "s")
    engine.defrule("first: if A.a == 0 then A.a = 1", "s")
    engine.defrule("second: if A.a == 1 then A.b = 1", "s")
    engine.fire("s")
    assert (engine.get("A.a"), engine.get("A.b"), engine.get("A.c")) == (1.0, 1.0, 10.0)


def test_fire_runs_only_the_named_rule_set():
    engine = ClipsEngine()
    engine.declare("A.x", 1)
    engine.declare("A.hits", 0)
    engine.defrule("one: if A.x == 1 then A.hits = A.hits + 1", "first")
    engine.defrule("ten: if A.x == 1 then A.hits = A.hits + 10", "second")
    engine.fire("first")
    engine.fire("first")
    assert engine.get("A.hits") == 2
    engine.fire("second")
    assert engine.get("A.hits") == 12


def test_unqualified_names_resolve_when_unambiguous():
    engine = ClipsEngine()
    engine.declare("Control.speed", 3)
    engine.declare("Robot.speed", 4)
    engine.declare("Robot.angle", 9)
    engine.set("angle", 10)
    assert engine.get("Robot.angle") == 10
    with pytest.raises(RuleError, match="ambiguous") as info:
        engine.defrule("r: if speed > 1 then angle = 0", "s")
    assert info.value.column == 7


def test_replace_by_label_keeps_the_position():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.declare("A.trace", "")
    assert engine.defrule("a: if A.x == 0 then A.trace = 'a'", "s") == "a"
    engine.defrule("b: if A.x == 0 then A.trace = 'b'", "s")
    engine.fire("s")
    assert engine.get("A.trace") == "b"  # b fires after a
    engine.defrule("a: if A.x == 0 then A.trace = 'a2'", "s")
    assert engine.rules("s") == ["a", "b"]
    engine.fire("s")
    assert engine.get("A.trace") == "b"  # still first: b still overwrites it
    engine.defrule("b: if A.x == 99 then A.trace = 'b2'", "s")
    engine.fire("s")
    assert engine.get("A.trace") == "a2"


def test_unlabelled_rules_get_labels():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    assert engine.defrule("if A.x == 0 then A.x = 1", "s") == "rule1"
    assert engine.defrule("if A.x == 1 then A.x = 2", "s") == "rule2"
    engine.fire("s")
    assert engine.get("A.x") == 2.0


def test_native_rules_read_globals_assign_and_call():
    engine = ClipsEngine()
    engine.declare("Control.speed", 0)
    engine.declare("Robot.mode", "run")
    called = []
    engine.bind_operation("Robot.beep", lambda *args: called.append(args))
    label = engine.defrule(
        """(defrule halt (acord-fire) (test (= ?*Control.speed* 0))
             => (acord-assign "Robot.mode" "halted") (acord-op "Robot.beep" 2 "x"))""",
        "native",
    )
    assert label == "halt"
    engine.fire("native")
    assert engine.get("Robot.mode") == "halted"
    assert called == [(2, "x")]
    engine.set("Control.speed", 3)
    engine.set("Robot.mode", "run")
    engine.fire("native")
    assert engine.get("Robot.mode") == "run"
    assert called == [(2, "x")]


def test_native_and_crisp_replace_each_other_by_label():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.defrule("r: if A.x == 0 then A.x = 1", "s")
    engine.defrule('(defrule s::r (acord-fire) => (acord-assign "A.x" 7))', "s")
    engine.fire("s")
    assert engine.get("A.x") == 7
    assert engine.rules("s") == ["r"]
    engine.set("A.x", 0)
    engine.defrule("r: if A.x == 0 then A.x = 2", "s")
    engine.fire("s")
    assert engine.get("A.x") == 2.0


def test_a_failed_redefinition_keeps_the_old_rule():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.defrule("r: if A.x == 0 then A.x = 1", "s")
    with pytest.raises(RuleError, match="CLIPS rejected") as info:
        engine.defrule("(defrule r (acord-fire) => (no-such-function))", "s")
    assert info.value.rule == "r" and info.value.ruleset == "s"
    engine.fire("s")
    assert engine.get("A.x") == 1.0


@pytest.mark.parametrize(
    ("rule", "message", "column"),
    [
        ("r: if A.x == then A.x = 1", "unexpected 'then'", 14),
        ("r: if A.nope > 1 then A.x = 1", "unknown variable 'A.nope'", 7),
        ("r: if A.x > 1 then A.y = 1", "unknown variable 'A.y'", 20),
        ("r: if A.x then A.x = 1 and 3", "unexpected", None),
        ("r: if 3 then A.x = 1", "must be true or false", None),
        ("r: if A.x > 1e999 then A.x = 1", "finite", None),
        ("r: if A.x > 1\nthen A.x = 1", "one line", None),
        ("(deffunction f () 1)", "one \\(defrule", 1),
        ("(defrule other::r (acord-fire) => )", "module 'other'", 10),
        ("(defrule r (acord-fire) => (bind ?x 1)) (assert (pwned))", "CLIPS rejected", None),
        ('(defrule r (acord-fire) => (printout t "unclosed)', "CLIPS rejected", None),
    ],
)
def test_bad_rules_raise_rule_errors_with_place(rule, message, column):
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    with pytest.raises(RuleError, match=message) as info:
        engine.defrule(rule, "policy")
    err = info.value
    assert err.ruleset == "policy"
    if column is not None:
        assert err.column == column
    assert "policy" in str(err)
    assert not [f for f in engine._bridge.env.facts() if "pwned" in str(f)]


def test_bad_rule_set_names_and_unknown_sets():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    for name in ("MAIN", "has space", "a::b", "(x)", "1st", ""):
        with pytest.raises(RuleError, match="cannot name a rule set"):
            engine.defrule("if A.x == 0 then A.x = 1", name)
    with pytest.raises(RuleError, match="no rule set 'nothing'"):
        engine.fire("nothing")


def test_declared_operations_are_checked_at_defrule():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.declare_operation("Robot.turn", ["angle"])
    with pytest.raises(RuleError, match=r"unknown operation 'Robot\.jump'") as info:
        engine.defrule("r: if A.x == 0 then Robot.jump()", "s")
    assert info.value.column == 21
    with pytest.raises(RuleError, match="takes 1 argument"):
        engine.defrule("r: if A.x == 0 then Robot.turn()", "s")
    engine.defrule("r: if A.x == 0 then turn(15)", "s")


def test_unbound_and_raising_operations_are_counted_and_the_fire_goes_on(caplog):
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.declare("A.done", False)
    calls = []

    def boom(value):
        raise RuntimeError(f"broken with {value}")

    engine.bind_operation("Robot.boom", boom)
    engine.bind_operation("Robot.after", lambda: calls.append("after"))
    engine.defrule("r: if A.x == 0 then Robot.missing() and Robot.boom(A.x) and A.done = true", "s")
    engine.defrule("s2: if A.done then Robot.after()", "s")
    with caplog.at_level(logging.WARNING, logger="acordcs.engines.clips"):
        engine.fire("s")
        engine.fire("s")
    assert engine.get("A.done") is True
    assert calls == ["after", "after"]
    assert engine.error_count == 4
    messages = [str(e) for e in engine.errors]
    assert "rule set 's', rule 'r': operation 'Robot.missing' is not bound" in messages[0]
    assert "bind_operation" in messages[0]
    assert "RuntimeError: broken with 0" in messages[1]
    warnings = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warnings) == 2  # each distinct problem is logged once, then only counted
    assert all(r.exc_info is None for r in warnings)


def test_evaluation_errors_make_the_condition_false():
    engine = ClipsEngine()
    engine.declare("A.x", 1)
    engine.declare("A.name", "text")
    engine.declare("A.out", 0)
    engine.defrule("div: if A.x / 0 > 1 then A.out = 1", "s")
    engine.defrule("mix: if A.name < 3 then A.out = 2", "s")
    engine.defrule("act: if A.x == 1 then A.out = A.name * 2 and A.x = 5", "s")
    engine.fire("s")
    assert engine.get("A.out") == 0
    assert engine.get("A.x") == 5.0  # the failing action is skipped, the next one runs
    assert {e.rule for e in engine.errors} == {"div", "mix", "act"}
    assert any("division by zero" in e.message for e in engine.errors)
    assert any(
        "needs two numbers or two strings, not string and number" in e.message
        for e in engine.errors
    )


def test_nan_follows_ieee():
    engine = ClipsEngine()
    engine.declare("A.x", math.nan)
    engine.declare("A.hits", "")
    engine.defrule("eq: if A.x == A.x then A.hits = A.hits", "s")
    engine.defrule("ne: if A.x != 0 then A.hits = 'ne'", "s")
    engine.defrule("lt: if A.x < 1 or A.x >= 1 then A.hits = 'ordered'", "s")
    engine.defrule("prop: if A.x != 1 then A.x = A.x + 1", "s")
    engine.fire("s")
    assert engine.get("A.hits") == "ne"
    assert math.isnan(engine.get("A.x"))
    assert engine.error_count == 0


@pytest.mark.parametrize(
    "evil",
    [
        '") (assert (pwned))',
        '\\") (assert (pwned)) ; ',
        "\\",
        "(defrule x => (assert (pwned)))",
        "?*acord-out* ; ) (bind ?*acord-cycle* 0)",
        "ünïcødé \t ☃",
    ],
)
def test_strings_never_become_clips_code(evil):
    engine = ClipsEngine()
    engine.declare("A.name", "")
    engine.declare("A.copy", "")
    engine.declare("A.same", False)
    engine.defrule("copy: if A.name != '' then A.copy = A.name", "s")
    engine.defrule("""same: if A.name == '") (assert (pwned))' then A.same = true""", "s")
    engine.set("A.name", evil)
    engine.fire("s")
    assert engine.get("A.copy") == evil
    assert engine.get("A.same") is (evil == '") (assert (pwned))')
    assert not [f for f in engine._bridge.env.facts() if "pwned" in str(f)]
    assert engine.error_count == 0


def test_string_constants_with_quotes_and_backslashes_compile_exactly():
    engine = ClipsEngine()
    engine.declare("A.name", "")
    engine.defrule("""a: if true then A.name = '\\" (assert (pwned)) "\\'""", "s")
    engine.fire("s")
    assert engine.get("A.name") == '\\" (assert (pwned)) "\\'
    assert not [f for f in engine._bridge.env.facts() if "pwned" in str(f)]


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("a\x00b", "NUL"),
        ("\ud800", "surrogate"),
        (2**70, "64 bits"),
        ([1, 2], "not a rule value"),
        (object(), "not a rule value"),
        ("fast", "declared number"),
        (True, "declared number"),
    ],
)
def test_bad_values_are_refused_by_set(value, message):
    engine = ClipsEngine()
    engine.declare("A.speed", 0, type="double")
    with pytest.raises(RuleError, match=message) as info:
        engine.set("A.speed", value)
    assert "A.speed" in str(info.value)
    assert engine.get("A.speed") == 0


def test_unknown_variables_in_set_and_get():
    lenient = ClipsEngine()
    lenient.set("Robot.speed", 3)  # declares it
    assert lenient.get("speed") == 3
    with pytest.raises(RuleError, match="not a variable name"):
        lenient.set("bad name", 1)
    strict = ClipsEngine(strict=True)
    strict.declare("Robot.speed", 0)
    with pytest.raises(RuleError, match=r"did you mean Robot\.speed"):
        strict.set("Robot.sped", 1)
    with pytest.raises(RuleError, match="unknown variable 'nothing'"):
        strict.get("nothing")


def test_values_keep_their_types_through_clips():
    engine = ClipsEngine()
    for name, value in [("A.i", 7), ("A.f", 2.5), ("A.s", "x"), ("A.b", True), ("A.n", None)]:
        engine.declare(name, value)
    engine.defrule(
        "r: if A.b then A.i = -(A.i * A.i) and A.f = -A.f and A.s = 'y' and A.b = false and A.n = A.i",
        "s",
    )
    engine.fire("s")
    assert [engine.get(n) for n in ("A.i", "A.f", "A.s", "A.b", "A.n")] == [
        -49,
        -2.5,
        "y",
        False,
        -49,
    ]
    assert type(engine.get("A.i")) is int  # integers stay integers unless mixed with a literal


def test_a_native_rule_that_never_settles_is_stopped_and_counted():
    engine = ClipsEngine(max_firings=50)
    engine.declare("A.x", 0)
    engine.defrule("(defrule start (acord-fire) => (assert (n 0)))", "loop")
    engine.defrule("(defrule step ?f <- (n ?k) => (retract ?f) (assert (n (+ ?k 1))))", "loop")
    engine.fire("loop")
    assert engine.error_count == 1
    assert "stopped after 50 rule firings" in engine.errors[0].message
    engine.defrule("r: if A.x == 0 then A.x = 1", "other")
    engine.fire("other")
    assert engine.get("A.x") == 1.0


def test_a_native_rule_that_errors_is_counted_and_the_engine_recovers():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.declare("A.y", 0)
    engine.defrule(
        '(defrule a (declare (salience 10)) (acord-fire) => (acord-assign "A.y" 1))', "s"
    )
    engine.defrule("(defrule bad (acord-fire) => (bind ?z (/ 1 0)))", "s")
    engine.fire("s")
    assert engine.error_count == 1
    assert "divide by zero" in engine.errors[0].message
    assert engine.get("A.y") == 1  # what happened before the error stands
    engine.defrule("ok: if A.x == 0 then A.x = 2", "t")
    engine.set("A.x", 0)
    engine.fire("t")
    assert engine.get("A.x") == 2.0


def test_engine_from_the_model_declares_types_defaults_and_operations():
    control = create(
        "CtxMonitor",
        name="Control",
        attributes=[create("Attribute", name="speed", type="double", defaultValue="0")],
    )
    recovery = create(
        "CtxComponent",
        name="Recovery",
        attributes=[
            create("Attribute", name="zeros", type="int", defaultValue="0"),
            create("Attribute", name="mode", type="String", defaultValue='"idle"'),
        ],
        operations=[
            create("Operation", name="recover"),
            create("Operation", name="askUser"),
            create("Operation", name="turn", parameters=[create("Parameter", name="angle")]),
        ],
    )
    policy = create(
        "CtxPolicy",
        name="recovery",
        rules=[create("Rule", label=r.split(":")[0], text=r.split(": ", 1)[1]) for r in RECOVERY],
    )
    policy_set = create("CtxPolicySet", name="Recovering", adapts=[recovery], policies=[policy])
    engine = engine_for_policy_set(policy_set, [control])
    assert engine.rules("recovery") == ["count", "retry", "giveup", "reset"]
    assert engine.get("Recovery.mode") == "idle"
    with pytest.raises(RuleError, match="takes 1 argument"):
        engine.defrule("if Control.speed > 1 then Recovery.turn()", "recovery")
    with pytest.raises(RuleError, match="declared number"):
        engine.set("Control.speed", "fast")
    with pytest.raises(RuleError, match="add it to the model"):
        engine.set("Control.rate", 1)
    component = Recovery()
    engine.bind("Recovery", component)
    engine.fire("recovery")
    assert component.log == ["recover"]


def test_one_call_into_clips_per_fire_and_no_construct_built_once_warm(monkeypatch):
    engine, _component = recovery_engine()
    engine.fire("recovery")  # pushes the declared initial values
    engine.set("Control.speed", 0)
    engine.fire("recovery")  # builds the push function of the pattern "Control.speed changed"
    bridge = engine._bridge
    counts = {"call": 0, "build": 0}
    real_call, real_build = bridge.call, bridge.build

    def counting_call(function, args):
        counts["call"] += 1
        return real_call(function, args)

    def counting_build(construct, module=None):
        counts["build"] += 1
        return real_build(construct, module)

    monkeypatch.setattr(bridge, "call", counting_call)
    monkeypatch.setattr(bridge, "build", counting_build)
    for speed in (0, 3, 0, 0, 5):
        engine.set("Control.speed", speed)
        engine.fire("recovery")
        engine.get("Recovery.zeros")
    assert counts == {"call": 5, "build": 0}


def test_the_generic_push_path_gives_the_same_results(monkeypatch):
    monkeypatch.setattr("acordcs.engines.clips.clips_engine._MAX_PUSHERS", 0)
    engine, component = recovery_engine()
    for speed in [0, 0, 0, 0, 7.5]:
        engine.set("Control.speed", speed)
        engine.fire("recovery")
    assert component.log == ["recover", "recover", "recover", "ask"]
    assert engine.get("Recovery.zeros") == 0.0
    assert engine._sets["recovery"].pushers == {}


def test_a_native_assignment_wakes_the_crisp_rules_that_read_it():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.declare("A.seen", False)
    engine.defrule("seen: if A.x == 5 then A.seen = true", "s")
    engine.defrule('(defrule five (acord-fire) => (acord-assign "A.x" 5))', "s")
    engine.defrule('(defrule typo (acord-fire) => (acord-assign "A.nope" 1))', "s")
    engine.fire("s")
    assert engine.get("A.x") == 5
    assert engine.get("A.seen") is True
    assert [e.message for e in engine.errors] == ["acord-assign: unknown variable A.nope"]


@pytest.mark.parametrize("declared", [None, "int", "string"])
def test_a_huge_integer_or_long_text_is_a_short_rule_error(declared):
    engine = ClipsEngine()
    engine.declare("A.x", 0 if declared != "string" else "", type=declared)
    for value in (10**5000, -(10**30), "9" * 5000):
        if declared != "int" and isinstance(value, str):
            continue  # an untyped or a string variable takes text
        with pytest.raises(RuleError) as caught:
            engine.set("A.x", value)
        assert len(str(caught.value)) < 300, str(caught.value)[:300]
