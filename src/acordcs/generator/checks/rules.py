"""Rules: syntax, and the paper's check that every variable is an attribute of a model element in the
policy set's scope; terms, outputs that are also inputs, operations and their arity."""

from __future__ import annotations

import difflib
from collections.abc import Iterator
from dataclasses import dataclass

from acordcs.generator.architecture import POLICY_SET, Role
from acordcs.generator.checks import Context, check
from acordcs.generator.checks.tags import variable_terms
from acordcs.generator.diagnostics import Diagnostic
from acordcs.generator.uml import Operation, Property
from acordcs.metamodel.rules import (
    Assign,
    Call,
    Consequent,
    Is,
    Name,
    Rule,
    RuleSyntaxError,
    names_in,
    parse_rule,
    split_rules,
)


@dataclass
class PolicyRule:
    """A rule as found in a policy's tag, with where it came from."""

    policy: Role
    tag: str
    index: int  # 1-based position among the tag's rules
    text: str
    line: int  # file line of the tag


def policy_rules(policy: Role) -> list[PolicyRule]:
    """Every rule of a CtxPolicy: the Rule tag and any tag whose name starts with Rule."""
    declared = policy.stereotype.tag("Rule")
    out = []
    for tag, value in policy.tags.items():
        if declared is None or not declared.matches(tag):
            continue
        for n, rule_line in enumerate(split_rules(value), start=1):
            out.append(PolicyRule(policy, tag, n, rule_line.text, policy.tag_line(tag)))
    return out


class _Scope:
    """Name resolution for one policy set: elements by name, attributes and operations by name.

    Indexed once per policy set: a model with hundreds of sets and thousands of rule atoms would
    otherwise scan the scope for every name.
    """

    def __init__(self, ctx: Context, policy_set: Role) -> None:
        self.ctx = ctx
        self.set = policy_set
        self.roles = ctx.arch.scope(policy_set)
        self.by_element: dict[str, list[Role]] = {}
        self.members: dict[str, dict[str, list[tuple[Role, object]]]] = {
            "attribute": {},
            "operation": {},
        }
        for role in self.roles:
            self.by_element.setdefault(role.name, []).append(role)
            element = role.element
            for kind, items in (
                ("attribute", getattr(element, "attributes", ())),
                ("operation", getattr(element, "operations", ())),
            ):
                for member in items:
                    self.members[kind].setdefault(member.name, []).append((role, member))

    def describe(self) -> str:
        return (
            ", ".join(r.name for r in self.roles)
            or "nothing: relate monitors and adapted elements to it"
        )

    def resolve(self, name: Name, kind: str) -> tuple[Role, Property | Operation] | str:
        """The (element, member) a name denotes, or a message saying why it denotes none."""
        found = self.members[kind].get(name.member, [])
        if name.element is not None:
            owners = self.by_element.get(name.element)
            if not owners:
                exists = any(r.name == name.element for r in self.ctx.arch.roles.values())
                why = (
                    f"{name.element!r} is not in the scope of policy set {self.set.name!r} (relate it: a "
                    "monitor feeding the set, or an element the set adapts)"
                    if exists
                    else f"no element named {name.element!r}"
                )
                return f"{why}; scope: {self.describe()}"
            found = [(r, m) for r, m in found if r.name == name.element]
            if not found:
                names = [m.name for r in owners for m in getattr(r.element, kind + "s", ())]
                return f"{name.element} has no {kind} {name.member!r}{_suggest(name.member, names)}"
            return found[0]
        if not found:
            names = list(self.members[kind])
            return (
                f"no element in the scope of policy set {self.set.name!r} has {kind} {name.member!r}"
                f"{_suggest(name.member, names)}; scope: {self.describe()}"
            )
        if len(found) > 1:
            return "ambiguous:" + ", ".join(f"{r.name}.{m.name}" for r, m in found)
        return found[0]


def _suggest(word: str, names: list[str]) -> str:
    # difflib is quadratic-ish: a bounded candidate list keeps huge hostile models fast
    close = difflib.get_close_matches(word, names[:500], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


@check
def rules(ctx: Context) -> Iterator[Diagnostic]:
    for policy_set in ctx.arch.of_kind(POLICY_SET):
        engine = policy_set.tag("engine") or "fuzzy"
        kind = "crisp" if engine == "clips" else "fuzzy"
        scope = _Scope(ctx, policy_set)
        labels: dict[str, PolicyRule] = {}
        # The set is one rule block: its engine fires all its policies' rules together.
        inputs: dict[str, Name] = {}
        outputs: list[tuple[str, Name, PolicyRule]] = []
        for policy in ctx.arch.policies(policy_set):
            found = policy_rules(policy)
            if not found:
                yield ctx.diag(
                    "L409",
                    f"policy {policy.name!r} has no rules: add a tag Rule with one rule per line",
                    policy,
                )
            for prule in found:
                where = f"rule {prule.index} of tag {prule.tag!r} of policy {policy.name!r}"
                try:
                    rule = parse_rule(prule.text, kind)
                except RuleSyntaxError as err:
                    yield ctx.diag(
                        "L401",
                        f"{where}, column {err.column}: {err.message}: {prule.text!r}",
                        policy,
                        line=prule.line,
                    )
                    continue
                if rule.label:
                    if rule.label in labels:
                        yield ctx.diag(
                            "L410",
                            f"{where}: label {rule.label!r} is also used by rule {labels[rule.label].index} "
                            f"of tag {labels[rule.label].tag!r}; defrule would replace one with the other",
                            policy,
                            line=prule.line,
                        )
                    labels[rule.label] = prule
                yield from _check_rule(ctx, scope, rule, prule, where, inputs, outputs)
        for attr_id, name, prule in outputs:
            if attr_id in inputs:
                yield ctx.diag(
                    "L405",
                    f"{name.text!r} is an output of rule {prule.index} of tag {prule.tag!r} and an "
                    f"input of policy set {policy_set.name!r}: a fuzzy rule block must not feed back "
                    "into itself",
                    prule.policy,
                    line=prule.line,
                )


def _check_rule(
    ctx, scope, rule: Rule, prule: PolicyRule, where, inputs, outputs
) -> Iterator[Diagnostic]:
    policy = prule.policy

    def problem(code: str, message: str, name: Name) -> Diagnostic:
        # The column is in the rule text, not in the XML line: it goes in the message, not the location.
        return ctx.diag(code, f"{where}, column {name.column}: {message}", policy, line=prule.line)

    def variable(name: Name):
        found = scope.resolve(name, "attribute")
        if isinstance(found, str):
            if found.startswith("ambiguous:"):
                options = found.removeprefix("ambiguous:")
                return problem(
                    "L403", f"{name.text!r} is ambiguous: it may be {options}; qualify it", name
                )
            return problem("L402", f"variable {name.text!r}: {found}", name)
        return found

    if rule.kind == "fuzzy":
        stack = [rule.condition]
        atoms: list[tuple[Is | Consequent, bool]] = []
        while stack:
            node = stack.pop()
            if isinstance(node, Is):
                atoms.append((node, True))
            elif hasattr(node, "operand"):
                stack.append(node.operand)
            elif hasattr(node, "left"):
                stack += [node.right, node.left]
        atoms += [(c, False) for c in rule.actions]
        for atom, is_input in atoms:
            found = variable(atom.var)
            if not isinstance(found, tuple):
                yield found
                continue
            _, attr = found
            var_role = ctx.arch.variable(attr)
            if var_role is None:
                yield problem(
                    "L408",
                    f"{atom.var.text!r} is not a linguistic variable: apply <<CtxVariable>> to the "
                    "attribute with tags min, max and terms",
                    atom.var,
                )
                continue
            terms = [t.name.text for t in variable_terms(var_role)]
            if terms and atom.term.text not in terms:
                shown = ", ".join(terms[:10]) + (
                    f", ... ({len(terms)} in all)" if len(terms) > 10 else ""
                )
                yield problem(
                    "L404",
                    f"{atom.var.text!r} has no term {atom.term.text!r} (its terms: {shown})"
                    f"{_suggest(atom.term.text, terms)}",
                    atom.term,
                )
            if is_input:
                inputs.setdefault(attr.id, atom.var)
            else:
                outputs.append((attr.id, atom.var, prule))
        return
    for name in rule.variables_read():
        found = variable(name)
        if not isinstance(found, tuple):
            yield found
    for action in rule.actions:
        if isinstance(action, Assign):
            found = variable(action.var)
            if not isinstance(found, tuple):
                yield found
            for name in names_in(action.value):
                found = variable(name)
                if not isinstance(found, tuple):
                    yield found
        elif isinstance(action, Call):
            yield from _check_call(ctx, scope, action, problem, variable)


def _check_call(ctx, scope, call: Call, problem, variable) -> Iterator[Diagnostic]:
    found = scope.resolve(call.target, "operation")
    if isinstance(found, str):
        if found.startswith("ambiguous:"):
            options = found.removeprefix("ambiguous:")
            yield problem(
                "L403", f"{call.target.text!r}() is ambiguous: {options}; qualify it", call.target
            )
        else:
            yield problem("L406", f"operation {call.target.text!r}: {found}", call.target)
    else:
        _, op = found
        expected = len(op.inputs)
        if expected != len(call.args):
            params = ", ".join(p.name for p in op.inputs)
            yield problem(
                "L407",
                f"{call.target.text}() takes {expected} argument(s) ({params}), given {len(call.args)}",
                call.target,
            )
    for arg in call.args:
        for name in names_in(arg):
            found_var = variable(name)
            if not isinstance(found_var, tuple):
                yield found_var
