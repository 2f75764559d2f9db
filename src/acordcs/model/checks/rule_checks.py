"""Rules: syntax, and the paper's check that every variable is an attribute of a model element in the
policy set's scope; terms, outputs that are also inputs, operations and their arity."""

from __future__ import annotations

from collections.abc import Iterator

from acordcs.diagnostics import Diagnostic
from acordcs.model import causes
from acordcs.model.architecture import POLICY_SET, Role
from acordcs.model.checks.check_context import Context
from acordcs.model.queries import (
    Ambiguous,
    PolicyRule,
    PolicySetScope,
    Resolved,
    Unresolved,
    policy_rules,
    rule_kind,
    suggestion,
    variable_terms,
)
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
)
from acordcs.xmi.uml import Property


def _where(prule: PolicyRule) -> str:
    # Only when there is something to report: most rules have nothing.
    return f"rule {prule.index} of tag {prule.tag!r} of policy {prule.policy.name!r}"


def file_column(prule: PolicyRule, column: int | None) -> int | None:
    """The file's column of the rule's column ``column``, when the file says where the rule
    starts (the text notation); None otherwise (an XMI tag: the column is the message's)."""
    if not prule.column or not column:
        return None
    return prule.column + column - 1


def _subject(prule: PolicyRule) -> str:
    """The rule's identity for fingerprints: its label, else tag and position (``Rule#2``)."""
    head = prule.text.split(":", 1)[0].strip() if ":" in prule.text else ""
    return head if head.isidentifier() else f"{prule.tag}#{prule.index}"


def rules(ctx: Context) -> Iterator[Diagnostic]:
    terms: dict[str, tuple[Role | None, list[str], set[str]]] = {}  # by attribute id, for all sets
    for policy_set in ctx.arch.of_kind(POLICY_SET):
        kind = rule_kind(policy_set)
        checker = _RuleChecker(ctx, PolicySetScope(ctx.arch, policy_set), terms)
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
                        column=file_column(prule, err.column),
                        subject=_subject(prule),
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
                            subject=_subject(prule),
                        )
                    labels[rule.label] = prule
                if rule.kind == "fuzzy":
                    yield from checker.fuzzy(rule, prule)
                else:
                    yield from checker.crisp(rule, prule)
        # The set is one rule block: its engine fires all its policies' rules together.
        yield from _feedback(ctx, policy_set, checker)


def _feedback(ctx: Context, policy_set: Role, checker: _RuleChecker) -> Iterator[Diagnostic]:
    """L405 once per output that is also an input of the set, with the rules concluding it."""
    concluding: dict[str, list[tuple[Name, PolicyRule]]] = {}
    for attr_id, name, prule in checker.outputs:
        if attr_id in checker.inputs:
            concluding.setdefault(attr_id, []).append((name, prule))
    for attr_id, found in concluding.items():
        name, first = found[0]
        read, reading = checker.inputs[attr_id]
        rules = [prule for _, prule in found]
        count = f"{len(rules)} rules" if len(rules) > 1 else "rule"
        written = f" (as {read.text!r})" if read.text != name.text else ""
        yield ctx.diag(
            "L405",
            f"{name.text!r} is an output of {count} ({_rules_named(rules)}) and an input of "
            f"{_rules_named([reading])}{written} in policy set {policy_set.name!r}: a fuzzy rule "
            "block must not feed back into itself; read it in another policy set, or conclude "
            "another attribute",
            first.policy,
            line=first.line,
            subject=name.text,
        )


def _rules_named(rules: list[PolicyRule]) -> str:
    """``rules 1-3, 5 of tag 'Rule' of policy 'P'; rule 2 of ...``: rules by tag and policy."""
    groups: dict[tuple[str, str], list[int]] = {}
    for prule in rules:
        groups.setdefault((prule.policy.name, prule.tag), []).append(prule.index)
    parts = []
    for (policy, tag), indexes in groups.items():
        numbers = _ranges(sorted(set(indexes)))
        word = "rules" if len(set(indexes)) > 1 else "rule"
        parts.append(f"{word} {numbers} of tag {tag!r} of policy {policy!r}")
    return "; ".join(parts)


def _ranges(numbers: list[int]) -> str:
    """``1-6, 8``: sorted numbers with runs shortened."""
    runs: list[list[int]] = []
    for n in numbers:
        if runs and n == runs[-1][-1] + 1:
            runs[-1].append(n)
        else:
            runs.append([n])
    return ", ".join(f"{r[0]}-{r[-1]}" if len(r) > 2 else ", ".join(map(str, r)) for r in runs)


class _RuleChecker:
    """The checks of the rules of one policy set, and what they gather about its rule block."""

    def __init__(self, ctx: Context, scope: PolicySetScope, terms: dict) -> None:
        self.ctx = ctx
        self.scope = scope
        self.terms = terms
        self.inputs: dict[str, tuple[Name, PolicyRule]] = {}  # by attribute id, the first read
        self.outputs: list[tuple[str, Name, PolicyRule]] = []

    def problem(
        self,
        prule: PolicyRule,
        code: str,
        message: str,
        name: Name,
        because: tuple[str, ...] = (),
    ) -> Diagnostic:
        # The column is in the rule text, not in the XML line: it goes in the message, and in the
        # location only when the file writes the rule on its own line (the text notation).
        return self.ctx.diag(
            code,
            f"{_where(prule)}, column {name.column}: {message}",
            prule.policy,
            line=prule.line,
            column=file_column(prule, name.column),
            subject=f"{_subject(prule)}:{name.text}",
            because=because,
        )

    def variable(
        self, prule: PolicyRule, name: Name, *, written: bool = False
    ) -> Resolved | Diagnostic:
        """What ``name`` denotes, or the diagnostic saying why it denotes nothing (with the keys
        of what would explain it: an element whose stereotype was not read, a lost relation);
        ``written``: the rule writes it."""
        found = self.scope.resolve(name, "attribute", written=written)
        if isinstance(found, Ambiguous):
            options = ", ".join(found.candidates)
            return self.problem(
                prule, "L403", f"{name.text!r} is ambiguous: it may be {options}; qualify it", name
            )
        if isinstance(found, Unresolved):
            return self.problem(
                prule, "L402", f"variable {name.text!r}: {found.reason}", name, found.because
            )
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
            found = self.variable(prule, var, written=index >= inputs)
            if not isinstance(found, Resolved):
                yield found
                continue
            attr = found.member
            info = self.terms.get(attr.id)
            if info is None:
                info = self._terms_of(attr)
            var_role, terms, known = info
            if var_role is None:
                # the attribute's <<CtxVariable>> unread (misspelt), or put on its class (T301)
                because: tuple[str, ...] = (causes.unread(attr.id),)
                if attr.owner is not None:
                    because += (causes.variable_of(attr.owner.id),)
                yield self.problem(
                    prule,
                    "L408",
                    f"{var.text!r} is not a linguistic variable: apply <<CtxVariable>> to the "
                    "attribute with tags min, max and terms",
                    var,
                    because,
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
                    f"{suggestion(atom.term.text, terms)}",
                    atom.term,
                )
            if index < inputs:
                self.inputs.setdefault(attr.id, (var, prule))
            else:
                self.outputs.append((attr.id, var, prule))

    def crisp(self, rule: Rule, prule: PolicyRule) -> Iterator[Diagnostic]:
        for name in rule.variables_read():
            found = self.variable(prule, name)
            if isinstance(found, Diagnostic):
                yield found
        for action in rule.actions:
            if isinstance(action, Assign):
                found = self.variable(prule, action.var, written=True)
                if isinstance(found, Diagnostic):
                    yield found
                for name in names_in(action.value):
                    found = self.variable(prule, name)
                    if isinstance(found, Diagnostic):
                        yield found
            elif isinstance(action, Call):
                yield from self.call(action, prule)

    def call(self, call: Call, prule: PolicyRule) -> Iterator[Diagnostic]:
        found = self.scope.resolve(call.target, "operation")
        if isinstance(found, Ambiguous):
            yield self.problem(
                prule,
                "L403",
                f"{call.target.text!r}() is ambiguous: {', '.join(found.candidates)}; qualify it",
                call.target,
            )
        elif isinstance(found, Unresolved):
            yield self.problem(
                prule,
                "L406",
                f"operation {call.target.text!r}: {found.reason}",
                call.target,
                found.because,
            )
        elif isinstance(found, Resolved):
            op = found.member
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
                if isinstance(found_var, Diagnostic):
                    yield found_var


CHECKS = (rules,)
"""This module's checks, in the order they run."""
