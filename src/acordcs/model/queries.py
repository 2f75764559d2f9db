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
from acordcs.diagnostics import suggestion
from acordcs.model import causes
from acordcs.model.architecture import MONITOR, PORT, Architecture, Role
from acordcs.rules import Name, RuleKind, RuleSyntaxError, TermDef, parse_terms, split_rules
from acordcs.rules.binding import RULE_SYNTAX, Scope, ScopeElement, Target, rule_syntax
from acordcs.rules.binding import Ambiguous as BoundAmbiguous
from acordcs.rules.binding import Unresolved as BoundUnresolved
from acordcs.typed_values import parse_integer, parse_real
from acordcs.xmi.uml import Element, Operation, Property


# ------------------------------------------------------------------------------------- rules
@dataclass
class PolicyRule:
    """A rule as found in a policy's tag, with where it came from."""

    policy: Role
    tag: str
    index: int  # 1-based position among the tag's rules
    text: str
    line: int  # file line of the tag (of the rule, when the file writes it on its own line)
    column: int = 0  # file column where the rule starts, when known (the text notation)


def policy_rules(policy: Role) -> list[PolicyRule]:
    """Every rule of a CtxPolicy: the Rule tag and any tag whose name starts with Rule."""
    declared = policy.stereotype.tag("Rule")
    out = []
    for tag, value in policy.tags.items():
        if declared is None or not declared.matches(tag):
            continue
        line = policy.tag_line(tag)
        placed = tag in policy.application.tag_places  # the file says where each rule is
        starts = _line_starts(value) if placed else []
        for n, rule_line in enumerate(split_rules(value), start=1):
            where = None
            if placed:
                start, raw = starts[rule_line.line - 1]
                offset = start + len(raw) - len(raw.lstrip())
                where = policy.application.place_in_file(tag, offset)
            if where is not None:
                out.append(PolicyRule(policy, tag, n, rule_line.text, *where))
            else:
                out.append(PolicyRule(policy, tag, n, rule_line.text, line))
    return out


def _line_starts(value: str) -> list[tuple[int, str]]:
    """Each line of ``value`` as split_rules splits it, with the offset where it starts."""
    out, offset = [], 0
    for raw in value.splitlines(keepends=True):
        out.append((offset, raw))
        offset += len(raw)
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
    """A name that denotes nothing in the scope; ``reason`` says why and what to do, for a
    person; ``because``: the keys of what would explain it (:mod:`acordcs.model.causes`: the
    element it names plays no role because its stereotype was not read, or a lost relation would
    have put it in the scope)."""

    reason: str
    because: tuple[str, ...] = ()


Resolution = Resolved | Ambiguous | Unresolved
MemberKind = str  # "attribute" or "operation"


class PolicySetScope:
    """The validator's view of a policy set's scope: :func:`acordcs.rules.binding` resolution
    (:func:`policy_scope`) with its answers worded for a person."""

    def __init__(self, arch: Architecture, policy_set: Role) -> None:
        self.arch = arch
        self.policy_set = policy_set
        self.scope = policy_scope(arch, policy_set)
        self._answers: dict[tuple[str, MemberKind, bool], Resolution] = {}

    def describe(self) -> str:
        """The scope's element names, for messages."""
        return (
            ", ".join(e.shown for e in self.scope.elements)
            or "nothing: relate monitors and adapted elements to it"
        )

    def resolve(self, name: Name, kind: MemberKind, *, written: bool = False) -> Resolution:
        """What ``name`` denotes among the scope's attributes (``kind`` "attribute") or operations;
        ``written``: the rule writes it (a fuzzy conclusion, an assignment), which decides where a
        missing attribute belongs (an element the set adapts, not a monitor)."""
        key = (name.text, kind, written)
        answer = self._answers.get(key)
        if answer is None:
            found = self.scope.resolve(name.text, kind)  # type: ignore[arg-type]
            answer = self._answers[key] = self._worded(found, kind, written)
        return answer

    def _misapplied(self, found: BoundUnresolved, kind: MemberKind) -> Element | None:
        """The element playing no role (its stereotype not read) the name may refer to, if any."""
        for element in self.arch.misapplied.values():
            if found.element is not None and found.element != element.name:
                continue
            members = getattr(element, "attributes" if kind == "attribute" else "operations", ())
            if found.element is not None or any(m.name == found.member for m in members):
                return element
        return None

    def _out_of_scope(self, found: BoundUnresolved, kind: MemberKind) -> list[Role]:
        """The roles outside the scope the name would denote were they in it."""
        inside = {e.origin.id for e in self.scope.elements}  # type: ignore[attr-defined]
        if found.element is not None:
            named = self.arch.roles_with("element", found.element)
        else:
            named = self.arch.roles_with(kind, found.member)
        return list({r.id: r for r in named if r.id not in inside}.values())

    def _scope_keys(self, role: Role) -> tuple[str, ...]:
        """What would have put ``role`` in the scope: a monitor feeding the set, or the set adapting
        it (or, for a port, the component owning it)."""
        ps = self.policy_set.id
        if role.kind == MONITOR:
            return (
                causes.pair("feeds", role.id, ps),
                causes.maybe("feeds", ps, causes.TARGET),
                causes.maybe("feeds", role.id, causes.SOURCE),
            )
        adapted = [role, *(self.arch.related_to(role, "owns_port") if role.kind == PORT else ())]
        keys = [causes.maybe("adapts", ps, causes.SOURCE)]
        for target in adapted:
            keys += [
                causes.pair("adapts", ps, target.id),
                causes.maybe("adapts", target.id, causes.TARGET),
            ]
        if role.kind == PORT:
            keys.append(causes.lacks("owns_port", role.id, causes.TARGET))
        return tuple(keys)

    def _next_step(self, member: str, kind: MemberKind, written: bool) -> str:
        """Where a missing member belongs: the one monitor feeding the set (what a rule reads), or
        the one element it adapts (what a rule writes or calls); else any element of the scope."""
        if not self.scope.elements:
            return ""  # the scope's description says to relate elements to the set
        name = self.policy_set.name
        if written or kind == "operation":
            where = self.arch.related(self.policy_set, "adapts")
            what = f"what policy set {name!r} adapts"
        else:
            where = self.arch.related_to(self.policy_set, "feeds")
            what = f"the monitor feeding policy set {name!r}"
        if len(where) == 1:
            return f"; add {kind} {member!r} to {self.arch.element_name(where[0])} ({what})"
        return (
            f"; add {kind} {member!r} to the element of the scope it belongs to, or qualify the "
            "name with it"
        )

    def _worded(self, found: object, kind: MemberKind, written: bool) -> Resolution:
        if isinstance(found, Target):
            return Resolved(found.element.origin, found.payload)  # type: ignore[arg-type]
        if isinstance(found, BoundAmbiguous):
            return Ambiguous(tuple(f"{t.element.shown}.{t.member}" for t in found.candidates))
        assert isinstance(found, BoundUnresolved)
        unread = self._misapplied(found, kind)
        because: tuple[str, ...] = (causes.unread(unread.id),) if unread is not None else ()
        outside = self._out_of_scope(found, kind)
        for role in outside:
            because += self._scope_keys(role)
        name = self.policy_set.name
        relate = "relate it: a monitor feeding the set, or an element the set adapts"
        if found.element is not None and not found.owners:
            if outside:
                why = f"{found.element!r} is not in the scope of policy set {name!r} ({relate})"
            else:
                shown = [e.shown for e in self.scope.elements]
                why = f"no element named {found.element!r}{suggestion(found.element, shown)}"
            return Unresolved(f"{why}; scope: {self.describe()}", because)
        hint = suggestion(found.member, list(found.known))
        if found.element is not None:
            if not hint:
                hint = f"; add {kind} {found.member!r} to {found.element}"
                if found.known:
                    hint += f", or use one of its {kind}s: {', '.join(found.known[:10])}"
            return Unresolved(f"{found.element} has no {kind} {found.member!r}{hint}", because)
        if not hint and outside:
            having = ", ".join(self.arch.element_name(r) for r in outside[:3])
            hint = (
                f"; {having} {'has' if len(outside) == 1 else 'have'} it but "
                f"{'is' if len(outside) == 1 else 'are'} not in the scope ({relate})"
            )
        elif not hint:
            hint = self._next_step(found.member, kind, written)
        return Unresolved(
            f"no element in the scope of policy set {name!r} has {kind} "
            f"{found.member!r}{hint}; scope: {self.describe()}",
            because,
        )


__all__ = [
    "ACQUISITIONS",
    "Ambiguous",
    "PolicyRule",
    "PolicySetScope",
    "Resolution",
    "Resolved",
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
