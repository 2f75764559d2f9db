"""Rules: syntax, and the paper's check that every variable is an attribute of a model element in the
policy set's scope; terms, outputs that are also inputs, operations and their arity."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from acordcs.diagnostics import Diagnostic
from acordcs.model.architecture import POLICY_SET, Role
from acordcs.model.checks import Context, check
from acordcs.model.checks.tags import variable_terms
from acordcs.rules import (
    Assign,
    BoolOp,
    Call,
    Consequent,
    Is,
    Name,
    Not,
    Rule,
    RuleSyntaxError,
    names_in,
    parse_rule,
    split_rules,
)
from acordcs.xmi.uml import Operation, Property


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
        line = policy.tag_line(tag)
        for n, rule_line in enumerate(split_rules(value), start=1):
            out.append(PolicyRule(policy, tag, n, rule_line.text, line))
    return out


class _Scope:
    """Name resolution for one policy set: elements by name, attributes and operations by name.

    Indexed once per policy set: a model with hundreds of sets and thousands of rule atoms would
    otherwise scan the scope for every name. Answers are kept by (text, kind): the same variables
    recur in every rule of a set, and an answer depends on nothing else (not on the column).
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
        self.answers: dict[tuple[str, str], tuple[Role, Property | Operation] | str] = {}
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
        key = (name.text, kind)
        answer = self.answers.get(key)
        if answer is None:
            answer = self.answers[key] = self._resolve(name, kind)
        return answer

    def _resolve(self, name: Name, kind: str) -> tuple[Role, Property | Operation] | str:
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
    import difflib  # only when a name is not found: it costs start-up time

    close = difflib.get_close_matches(word, names[:500], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _where(prule: PolicyRule) -> str:
    # Only when there is something to report: most rules have nothing.
    return f"rule {prule.index} of tag {prule.tag!r} of policy {prule.policy.name!r}"


@check
def rules(ctx: Context) -> Iterator[Diagnostic]:
    terms: dict[str, tuple[Role | None, list[str], set[str]]] = {}  # by attribute id, for all sets
    for policy_set in ctx.arch.of_kind(POLICY_SET):
        engine = policy_set.tag("engine") or "fuzzy"
        kind = "crisp" if engine == "clips" else "fuzzy"
        checker = _RuleChecker(ctx, _Scope(ctx, policy_set), terms)
        labels: dict[str, PolicyRule] = {}
        for policy in ctx.arch.policies(policy_set):
            found = policy_rules(policy)
            if not found:
                yield ctx.diag(
                    "L409",
                    f"policy {policy.name!r} has no rules: add a tag Rule with one rule per line",
                    policy,
                )
            for prule in found:
                try:
                    rule = parse_rule(prule.text, kind)
                except RuleSyntaxError as err:
                    yield ctx.diag(
                        "L401",
                        f"{_where(prule)}, column {err.column}: {err.message}: {prule.text!r}",
                        policy,
                        line=prule.line,
                    )
                    continue
                if rule.label:
                    if rule.label in labels:
                        yield ctx.diag(
                            "L410",
                            f"{_where(prule)}: label {rule.label!r} is also used by rule "
                            f"{labels[rule.label].index} of tag {labels[rule.label].tag!r}; defrule "
                            "would replace one with the other",
                            policy,
                            line=prule.line,
                        )
                    labels[rule.label] = prule
                if rule.kind == "fuzzy":
                    yield from checker.fuzzy(rule, prule)
                else:
                    yield from checker.crisp(rule, prule)
        # The set is one rule block: its engine fires all its policies' rules together.
        for attr_id, name, prule in checker.outputs:
            if attr_id in checker.inputs:
                yield ctx.diag(
                    "L405",
                    f"{name.text!r} is an output of rule {prule.index} of tag {prule.tag!r} and an "
                    f"input of policy set {policy_set.name!r}: a fuzzy rule block must not feed back "
                    "into itself",
                    prule.policy,
                    line=prule.line,
                )


class _RuleChecker:
    """The checks of the rules of one policy set, and what they gather about its rule block."""

    def __init__(self, ctx: Context, scope: _Scope, terms: dict) -> None:
        self.ctx = ctx
        self.scope = scope
        self.terms = terms
        self.inputs: dict[str, Name] = {}
        self.outputs: list[tuple[str, Name, PolicyRule]] = []

    def problem(self, prule: PolicyRule, code: str, message: str, name: Name) -> Diagnostic:
        # The column is in the rule text, not in the XML line: it goes in the message, not the location.
        return self.ctx.diag(
            code, f"{_where(prule)}, column {name.column}: {message}", prule.policy, line=prule.line
        )

    def variable(
        self, prule: PolicyRule, name: Name
    ) -> tuple[Role, Property | Operation] | Diagnostic:
        found = self.scope.resolve(name, "attribute")
        if isinstance(found, str):
            if found.startswith("ambiguous:"):
                options = found.removeprefix("ambiguous:")
                return self.problem(
                    prule,
                    "L403",
                    f"{name.text!r} is ambiguous: it may be {options}; qualify it",
                    name,
                )
            return self.problem(prule, "L402", f"variable {name.text!r}: {found}", name)
        return found

    def _terms_of(self, attr: Property) -> tuple[Role | None, list[str], set[str]]:
        # Depends on the attribute only: kept for every policy set of the run.
        var_role = self.ctx.arch.variable(attr)
        names = [] if var_role is None else [t.name.text for t in variable_terms(var_role)]
        info = self.terms[attr.id] = (var_role, names, set(names))
        return info

    def fuzzy(self, rule: Rule, prule: PolicyRule) -> Iterator[Diagnostic]:
        atoms: list[Is | Consequent] = []  # inputs in order of appearance, then outputs
        stack = [rule.condition]
        while stack:
            node = stack.pop()
            kind = node.__class__
            if kind is Is:
                atoms.append(node)
            elif kind is BoolOp:  # the common nodes first; hasattr costs an exception
                stack += (node.right, node.left)
            elif kind is Not or hasattr(node, "operand"):
                stack.append(node.operand)
            elif hasattr(node, "left"):
                stack += [node.right, node.left]
        inputs = len(atoms)
        atoms += rule.actions
        for index, atom in enumerate(atoms):
            var = atom.var
            found = self.variable(prule, var)
            if not isinstance(found, tuple):
                yield found
                continue
            attr = found[1]
            info = self.terms.get(attr.id)
            if info is None:
                info = self._terms_of(attr)
            var_role, terms, known = info
            if var_role is None:
                yield self.problem(
                    prule,
                    "L408",
                    f"{var.text!r} is not a linguistic variable: apply <<CtxVariable>> to the "
                    "attribute with tags min, max and terms",
                    var,
                )
                continue
            if terms and atom.term.text not in known:
                shown = ", ".join(terms[:10]) + (
                    f", ... ({len(terms)} in all)" if len(terms) > 10 else ""
                )
                yield self.problem(
                    prule,
                    "L404",
                    f"{var.text!r} has no term {atom.term.text!r} (its terms: {shown})"
                    f"{_suggest(atom.term.text, terms)}",
                    atom.term,
                )
            if index < inputs:
                self.inputs.setdefault(attr.id, var)
            else:
                self.outputs.append((attr.id, var, prule))

    def crisp(self, rule: Rule, prule: PolicyRule) -> Iterator[Diagnostic]:
        for name in rule.variables_read():
            found = self.variable(prule, name)
            if not isinstance(found, tuple):
                yield found
        for action in rule.actions:
            if isinstance(action, Assign):
                found = self.variable(prule, action.var)
                if not isinstance(found, tuple):
                    yield found
                for name in names_in(action.value):
                    found = self.variable(prule, name)
                    if not isinstance(found, tuple):
                        yield found
            elif isinstance(action, Call):
                yield from self.call(action, prule)

    def call(self, call: Call, prule: PolicyRule) -> Iterator[Diagnostic]:
        found = self.scope.resolve(call.target, "operation")
        if isinstance(found, str):
            if found.startswith("ambiguous:"):
                options = found.removeprefix("ambiguous:")
                yield self.problem(
                    prule,
                    "L403",
                    f"{call.target.text!r}() is ambiguous: {options}; qualify it",
                    call.target,
                )
            else:
                yield self.problem(
                    prule, "L406", f"operation {call.target.text!r}: {found}", call.target
                )
        else:
            _, op = found
            expected = len(op.inputs)
            if expected != len(call.args):
                params = ", ".join(p.name for p in op.inputs)
                yield self.problem(
                    prule,
                    "L407",
                    f"{call.target.text}() takes {expected} argument(s) ({params}), given "
                    f"{len(call.args)}",
                    call.target,
                )
        for arg in call.args:
            for name in names_in(arg):
                found_var = self.variable(prule, name)
                if not isinstance(found_var, tuple):
                    yield found_var
