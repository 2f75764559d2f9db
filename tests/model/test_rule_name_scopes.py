"""The ``rules`` check (acordcs.model.checks.rule_checks) resolves each name of a rule in the scope of its
own policy set (the monitors feeding the set, the elements it adapts): what one set may name must not
leak into another, for fuzzy variables and terms as for crisp names and calls."""

from __future__ import annotations

from tests.support.toolchain import rule_and_tag_findings


def _policy_set(gen, pkg, name: str, rules_text: str, feeders, adapted, engine="fuzzy"):
    pset = gen.ctx(pkg.cls(name), "CtxPolicySet", engine=engine, trigger="event")
    policy = gen.ctx(pkg.cls(f"{name}Rules"), "CtxPolicy", Rule=rules_text)
    pkg.associate(pset, policy, "policy", aggregation="composite")
    for monitor in feeders:
        pkg.associate(monitor, pset, "feeds")
    for target in adapted:
        pkg.depend(pset, target)
    return pset


def test_a_name_resolves_in_its_own_policy_set_only(tmp_path) -> None:
    def build(gen, pkg):
        a = gen.ctx(pkg.cls("CompA"), "CtxComponent")
        gen.ctx_var(a, "speed", "double", 0, 10, "slow := trian 0 0 10; fast := trian 0 10 10")
        gen.ctx_var(a, "out", "double", 0, 1, "lo := trian 0 0 1; hi := trian 0 1 1")
        b = gen.ctx(pkg.cls("CompB"), "CtxComponent")
        gen.ctx_var(b, "speed", "double", 0, 10, "low := trian 0 0 10; high := trian 0 10 10")
        gen.ctx_var(b, "out", "double", 0, 1, "lo := trian 0 0 1; hi := trian 0 1 1")
        b.attr("count", "int")
        mon = gen.ctx(pkg.cls("Mon"), "CtxMonitor")
        gen.ctx_var(mon, "load", "double", 0, 1, "lo := trian 0 0 1; hi := trian 0 1 1")
        _policy_set(
            gen,
            pkg,
            "SetA",
            "if speed is slow then out is hi\nif speed is low then out is lo",
            [mon],
            [a],
        )
        _policy_set(
            gen,
            pkg,
            "SetB",
            "if speed is low then out is hi\nif speed is slow then out is lo",
            [mon],
            [b],
        )
        both = "if speed is slow then CompA.out is hi\nif load is lo and  speed is x then CompB.out is lo\n"
        both += "if CompB.speed is high and sped is lo then CompA.out is hi\nif lod is lo then count is hi"
        _policy_set(gen, pkg, "SetAB", both, [mon], [a, b])

    found = rule_and_tag_findings(tmp_path, build)
    wanted = [
        ("L404", "rule 2 of tag 'Rule' of policy 'SetARules', column 13: 'speed' has no term 'low' (its terms: slow, fast) (did you mean 'slow'?)"),
        ("L404", "rule 2 of tag 'Rule' of policy 'SetBRules', column 13: 'speed' has no term 'slow' (its terms: low, high) (did you mean 'low'?)"),
        ("L403", "rule 1 of tag 'Rule' of policy 'SetABRules', column 4: 'speed' is ambiguous: it may be CompA.speed, CompB.speed; qualify it"),
        ("L403", "rule 2 of tag 'Rule' of policy 'SetABRules', column 20: 'speed' is ambiguous: it may be CompA.speed, CompB.speed; qualify it"),
        ("L402", "rule 3 of tag 'Rule' of policy 'SetABRules', column 28: variable 'sped': no element in the scope of policy set 'SetAB' has attribute 'sped' (did you mean 'speed'?); scope: Mon, CompA, CompB"),
        ("L402", "rule 4 of tag 'Rule' of policy 'SetABRules', column 4: variable 'lod': no element in the scope of policy set 'SetAB' has attribute 'lod' (did you mean 'load'?); scope: Mon, CompA, CompB"),
        ("L408", "rule 4 of tag 'Rule' of policy 'SetABRules', column 19: 'count' is not a linguistic variable: apply <<CtxVariable>> to the attribute with tags min, max and terms"),
    ]  # fmt: skip
    assert sorted(found) == sorted(wanted)


def test_crisp_names_and_calls_resolve_per_set(tmp_path) -> None:
    def build(gen, pkg):
        a = gen.ctx(pkg.cls("Robot"), "CtxComponent")
        a.attr("speed", "int")
        a.op("stop")
        b = gen.ctx(pkg.cls("Arm"), "CtxComponent")
        b.attr("speed", "int")
        b.op("stop", [("how", "int")])
        rules_a = "if speed > 1 then stop() and speed = speed - 1\nif sped > 1 then stop(1)"
        _policy_set(gen, pkg, "Drive", rules_a, [], [a], engine="clips")
        rules_b = "if speed > 1 then stop() and speed = speed - 1\nif speed > 1 then stop(2) and Robot.stop()"
        _policy_set(gen, pkg, "Grip", rules_b, [], [b], engine="clips")

    found = rule_and_tag_findings(tmp_path, build)
    wanted = [
        ("L402", "rule 2 of tag 'Rule' of policy 'DriveRules', column 4: variable 'sped': no element in the scope of policy set 'Drive' has attribute 'sped' (did you mean 'speed'?); scope: Robot"),
        ("L407", "rule 2 of tag 'Rule' of policy 'DriveRules', column 18: stop() takes 0 argument(s) (), given 1"),
        ("L407", "rule 1 of tag 'Rule' of policy 'GripRules', column 19: stop() takes 1 argument(s) (how), given 0"),
        ("L406", "rule 2 of tag 'Rule' of policy 'GripRules', column 31: operation 'Robot.stop': 'Robot' is not in the scope of policy set 'Grip' (relate it: a monitor feeding the set, or an element the set adapts); scope: Arm"),
    ]  # fmt: skip
    assert sorted(found) == sorted(wanted)
