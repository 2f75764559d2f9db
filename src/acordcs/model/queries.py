"""Questions asked of an interpreted model, shared by the checks, ``inspect``'s summary and the
pyecore model builder: a policy's rules, a tag read as a number, a variable's terms and range,
and which attribute or operation a rule's name denotes in a policy set's scope.

Answers that can fail say why in a typed result (:class:`Resolved`, :class:`Ambiguous`,
:class:`Unresolved`), never in a string to be parsed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from acordcs import vocabularies
from acordcs.descriptor.model import parse_integer, parse_real
from acordcs.diagnostics import suggestion
from acordcs.model.architecture import Architecture, Role
from acordcs.rules import Name, RuleKind, RuleSyntaxError, TermDef, parse_terms, split_rules
from acordcs.rules.binding import RULE_SYNTAX, Scope, ScopeElement, Target, rule_syntax
from acordcs.rules.binding import Ambiguous as BoundAmbiguous
from acordcs.rules.binding import Unresolved as BoundUnresolved
from acordcs.xmi.uml import Operation, Property


# ------------------------------------------------------------------------------------- rules
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


def rule_kind(policy_set: Role) -> RuleKind:
    """The syntax of a policy set's rules, by its engine (:func:`acordcs.rules.binding.rule_syntax`);
    an engine the metamodel does not know (reported by the tag checks) reads as the default
    engine's, so that its rules are not reported a second time."""
    engine = policy_set.tag("engine")
    return rule_syntax(engine if engine in RULE_SYNTAX else None)


# ----------------------------------------------------------------------- linguistic variables
_TERMS_CACHE: dict[str, list[TermDef] | RuleSyntaxError] = {}


ACQUISITIONS = vocabularies.ACQUISITIONS  # the metamodel's MonitorAcquisition


def monitor_acquisition(monitor: Role) -> str:
    """How ``monitor`` acquires context: its tag ``acquisition``, or when unset (or not one of
    :data:`ACQUISITIONS`, which the checks report) ``custom`` for a monitor with a frequency and
    ``intercept`` for one without."""
    tag = monitor.tag("acquisition")
    if tag in ACQUISITIONS:
        return tag
    return "custom" if parse_real(monitor.tag("frequency") or "") is not None else "intercept"


def parsed_terms(text: str) -> list[TermDef] | RuleSyntaxError:
    """``parse_terms`` memoised by text: a model has far fewer distinct term lists than variables,
    and every rule atom asks for its variable's terms."""
    if text not in _TERMS_CACHE:
        if len(_TERMS_CACHE) > 4096:
            _TERMS_CACHE.clear()
        try:
            _TERMS_CACHE[text] = parse_terms(text)
        except RuleSyntaxError as err:
            _TERMS_CACHE[text] = err
    return _TERMS_CACHE[text]


def variable_terms(role: Role) -> list[TermDef]:
    """The terms of a CtxVariable role; [] when missing or unparseable (reported by the check)."""
    terms = parsed_terms(role.tags.get("terms", ""))
    return [] if isinstance(terms, RuleSyntaxError) else terms


def variable_range(role: Role) -> tuple[float, float] | None:
    """A CtxVariable's universe (min, max), or None unless both are numbers and min < max."""
    lo = parse_real(role.tags.get("min", ""))
    hi = parse_real(role.tags.get("max", ""))
    return (lo, hi) if lo is not None and hi is not None and lo < hi else None


# ---------------------------------------------------------------------------- name resolution
def policy_scope(
    arch: Architecture,
    policy_set: Role,
    attribute: Callable[[Role, Property], object] = lambda role, prop: prop,
    operation: Callable[[Role, Operation], object] = lambda role, op: op,
) -> Scope:
    """The scope of ``policy_set``'s rules (:meth:`Architecture.scope`) for
    :mod:`acordcs.rules.binding`: each element under its application name, its role as origin,
    its attributes and operations with what ``attribute`` and ``operation`` make of them as
    payloads (the UML ones by default)."""
    return Scope(
        ScopeElement(
            arch.element_name(role),
            {p.name: attribute(role, p) for p in getattr(role.element, "attributes", ())},
            {o.name: operation(role, o) for o in getattr(role.element, "operations", ())},
            short=role.name,
            origin=role,
        )
        for role in arch.scope(policy_set)
    )


@dataclass(frozen=True)
class Resolved:
    """The element and its attribute or operation a rule's name denotes."""

    role: Role
    member: Property | Operation


@dataclass(frozen=True)
class Ambiguous:
    """An unqualified name that several elements of the scope have: ``Element.member`` each."""

    candidates: tuple[str, ...]


@dataclass(frozen=True)
class Unresolved:
    """A name that denotes nothing in the scope; ``reason`` says why, for a person."""

    reason: str


@dataclass(frozen=True)
class Unchecked:
    """A name that may denote a member of an element whose stereotype is misspelt (T302): not
    reported again, the stereotype is the cause."""

    element: str


Resolution = Resolved | Ambiguous | Unresolved | Unchecked
MemberKind = str  # "attribute" or "operation"


class PolicySetScope:
    """The validator's view of a policy set's scope: :func:`acordcs.rules.binding` resolution
    (:func:`policy_scope`) with its answers worded for a person."""

    def __init__(self, arch: Architecture, policy_set: Role) -> None:
        self.arch = arch
        self.policy_set = policy_set
        self.scope = policy_scope(arch, policy_set)
        self._answers: dict[tuple[str, MemberKind], Resolution] = {}

    def describe(self) -> str:
        """The scope's element names, for messages."""
        return (
            ", ".join(e.shown for e in self.scope.elements)
            or "nothing: relate monitors and adapted elements to it"
        )

    def resolve(self, name: Name, kind: MemberKind) -> Resolution:
        """What ``name`` denotes among the scope's attributes (``kind`` "attribute") or operations."""
        key = (name.text, kind)
        answer = self._answers.get(key)
        if answer is None:
            answer = self._answers[key] = self._worded(self.scope.resolve(name.text, kind), kind)  # type: ignore[arg-type]
        return answer

    def _misapplied(self, found: BoundUnresolved, kind: MemberKind) -> str | None:
        """The element with a misspelt stereotype the name may refer to, if any."""
        for element in self.arch.misapplied.values():
            if found.element is not None and found.element != element.name:
                continue
            members = getattr(element, "attributes" if kind == "attribute" else "operations", ())
            if found.element is not None or any(m.name == found.member for m in members):
                return element.name
        return None

    def _worded(self, found: object, kind: MemberKind) -> Resolution:
        if isinstance(found, Target):
            return Resolved(found.element.origin, found.payload)  # type: ignore[arg-type]
        if isinstance(found, BoundAmbiguous):
            return Ambiguous(tuple(f"{t.element.shown}.{t.member}" for t in found.candidates))
        assert isinstance(found, BoundUnresolved)
        cause = self._misapplied(found, kind)
        if cause is not None:
            return Unchecked(cause)
        name = self.policy_set.name
        if found.element is not None and not found.owners:
            exists = any(r.name == found.element for r in self.arch.roles.values())
            why = (
                f"{found.element!r} is not in the scope of policy set {name!r} "
                "(relate it: a monitor feeding the set, or an element the set adapts)"
                if exists
                else f"no element named {found.element!r}"
            )
            return Unresolved(f"{why}; scope: {self.describe()}")
        if found.element is not None:
            return Unresolved(
                f"{found.element} has no {kind} {found.member!r}"
                f"{suggestion(found.member, list(found.known))}"
            )
        return Unresolved(
            f"no element in the scope of policy set {name!r} has {kind} "
            f"{found.member!r}{suggestion(found.member, list(found.known))}; "
            f"scope: {self.describe()}"
        )


__all__ = [
    "ACQUISITIONS",
    "Ambiguous",
    "PolicyRule",
    "PolicySetScope",
    "Resolution",
    "Resolved",
    "Unchecked",
    "Unresolved",
    "monitor_acquisition",
    "parse_integer",
    "parse_real",
    "parsed_terms",
    "policy_rules",
    "policy_scope",
    "rule_kind",
    "variable_range",
    "variable_terms",
]
