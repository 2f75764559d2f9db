"""Questions asked of an interpreted model, shared by the checks, ``inspect``'s summary and the
pyecore model builder: a policy's rules, a tag read as a number, a variable's terms and range,
and which attribute or operation a rule's name denotes in a policy set's scope.

Answers that can fail say why in a typed result (:class:`Resolved`, :class:`Ambiguous`,
:class:`Unresolved`), never in a string to be parsed.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from acordcs import vocabularies
from acordcs.diagnostics import suggestion
from acordcs.model.architecture import Architecture, Role
from acordcs.rules import Name, RuleKind, RuleSyntaxError, TermDef, parse_terms, split_rules
from acordcs.xmi.uml import Operation, Property

# xsd:double and xsd:int lexical forms (ASCII digits only), as EMF and Java read tag values.
_REAL = re.compile(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?")
_INTEGER = re.compile(r"[+-]?[0-9]+")


def parse_real(text: str) -> float | None:
    """A tag value as a finite xsd:double, or None."""
    text = text.strip()
    if not _REAL.fullmatch(text):
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def parse_integer(text: str) -> int | None:
    """A tag value as an xsd:int-like integer (under 20 characters), or None."""
    text = text.strip()
    return int(text) if _INTEGER.fullmatch(text) and len(text) < 20 else None


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
    """The syntax of a policy set's rules: crisp for the CLIPS engine, else fuzzy."""
    return "crisp" if policy_set.tag("engine") == "clips" else "fuzzy"


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


Resolution = Resolved | Ambiguous | Unresolved
MemberKind = str  # "attribute" or "operation"


class PolicySetScope:
    """Name resolution for one policy set: its scope's elements by name, attributes and operations
    by name.

    Indexed once per policy set: a model with hundreds of sets and thousands of rule atoms would
    otherwise scan the scope for every name. Answers are kept by (text, kind): the same variables
    recur in every rule of a set, and an answer depends on nothing else (not on the column).
    """

    def __init__(self, arch: Architecture, policy_set: Role) -> None:
        self.arch = arch
        self.policy_set = policy_set
        self.roles = arch.scope(policy_set)
        self._by_element: dict[str, list[Role]] = {}
        self._members: dict[MemberKind, dict[str, list[Resolved]]] = {
            "attribute": {},
            "operation": {},
        }
        self._answers: dict[tuple[str, MemberKind], Resolution] = {}
        for role in self.roles:
            self._by_element.setdefault(role.name, []).append(role)
            element = role.element
            for kind, items in (
                ("attribute", getattr(element, "attributes", ())),
                ("operation", getattr(element, "operations", ())),
            ):
                for member in items:
                    self._members[kind].setdefault(member.name, []).append(Resolved(role, member))

    def describe(self) -> str:
        """The scope's element names, for messages."""
        return (
            ", ".join(r.name for r in self.roles)
            or "nothing: relate monitors and adapted elements to it"
        )

    def resolve(self, name: Name, kind: MemberKind) -> Resolution:
        """What ``name`` denotes among the scope's attributes (``kind`` "attribute") or operations."""
        key = (name.text, kind)
        answer = self._answers.get(key)
        if answer is None:
            answer = self._answers[key] = self._resolve(name, kind)
        return answer

    def _resolve(self, name: Name, kind: MemberKind) -> Resolution:
        found = self._members[kind].get(name.member, [])
        if name.element is not None:
            owners = self._by_element.get(name.element)
            if not owners:
                exists = any(r.name == name.element for r in self.arch.roles.values())
                why = (
                    f"{name.element!r} is not in the scope of policy set {self.policy_set.name!r} "
                    "(relate it: a monitor feeding the set, or an element the set adapts)"
                    if exists
                    else f"no element named {name.element!r}"
                )
                return Unresolved(f"{why}; scope: {self.describe()}")
            found = [r for r in found if r.role.name == name.element]
            if not found:
                names = [m.name for r in owners for m in getattr(r.element, kind + "s", ())]
                return Unresolved(
                    f"{name.element} has no {kind} {name.member!r}{suggestion(name.member, names)}"
                )
            return found[0]
        if not found:
            return Unresolved(
                f"no element in the scope of policy set {self.policy_set.name!r} has {kind} "
                f"{name.member!r}{suggestion(name.member, list(self._members[kind]))}; "
                f"scope: {self.describe()}"
            )
        if len(found) > 1:
            return Ambiguous(tuple(f"{r.role.name}.{r.member.name}" for r in found))
        return found[0]
