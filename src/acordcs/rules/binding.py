"""What the names in a policy set's rules stand for: the one resolution of rule names.

A policy set's rules name attributes (its variables) and operations of the elements in its scope:
the monitors feeding it, the elements it adapts and an adapted component's ports. A name is
``Element.member``, or a bare ``member`` that exactly one element of the scope has. An element is
named by its name (a port by its own name, ``LocomotionPort.rate``, or with its component,
``Locomotion.LocomotionPort.rate``).

:class:`Scope` answers for one policy set; :func:`bind` walks a set's parsed rules and says what
each name is bound to and what the engine needs around them: the variables set before each
firing, those read back after it, those whose change fires the set, the operations called.
Everything that resolves rule names calls these: the validator (to report what does not resolve),
the descriptor's builder (which writes the answers into the application descriptor, so that the
runtime and the generator read them instead of resolving again) and the runtime, for a policy set
built by hand in Python.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Literal

from acordcs.rules.tree import Assign, Call, Name, Rule, RuleKind, names_in
from acordcs.vocabularies import CLIPS_ENGINE, FUZZY_ENGINE

MemberKind = Literal["attribute", "operation"]

RULE_SYNTAX: dict[str, RuleKind] = {FUZZY_ENGINE: "fuzzy", CLIPS_ENGINE: "crisp"}
"""How the rules of a policy set are written, by its engine: the metamodel's two engines (an
engine registered at run time says its own: :func:`acordcs.engines.engine_registry.register_engine`)."""


def rule_syntax(engine: str | None) -> RuleKind:
    """The rule syntax of ``engine``: fuzzy for the fuzzy engine (and when none is given), crisp
    for any other."""
    return RULE_SYNTAX.get(engine or FUZZY_ENGINE, "crisp")


@dataclass(frozen=True, slots=True)
class ScopeElement:
    """An element of a policy set's scope: ``name`` as the application names it (a port:
    ``Component.Port``), ``short`` as rules may also qualify it (a port's own name), its
    attributes and operations by name with whatever the caller attaches to each (a UML property,
    a descriptor property, an operation's arity)."""

    name: str
    attributes: Mapping[str, object]
    operations: Mapping[str, object]
    short: str | None = None
    origin: object = None  # the caller's element (a model role, a descriptor element)

    @property
    def shown(self) -> str:
        """The name messages show: as rules most simply qualify it (a port's own name)."""
        return self.short or self.name


@dataclass(frozen=True, slots=True)
class Target:
    """What a name denotes: ``member``, an attribute or operation (``kind``) of ``element``, and
    the caller's object for it (``payload``). ``name`` is the canonical ``Element.member``."""

    element: ScopeElement
    member: str
    payload: object
    kind: MemberKind = "attribute"

    @property
    def name(self) -> str:
        return f"{self.element.name}.{self.member}"


@dataclass(frozen=True, slots=True)
class Ambiguous:
    """A bare name that several elements of the scope have."""

    candidates: tuple[Target, ...]


@dataclass(frozen=True, slots=True)
class Unresolved:
    """A name that denotes nothing in the scope. ``element`` is the qualifier as written (None for
    a bare name); ``owners`` the scope's elements of that name (empty: the qualifier names no element
    of the scope); ``known`` the names it could have meant (for "did you mean")."""

    member: str
    element: str | None
    owners: tuple[ScopeElement, ...]
    known: tuple[str, ...]


Resolution = Target | Ambiguous | Unresolved


class Scope:
    """Name resolution for one policy set, over its scope's elements in order. Answers are kept by
    (name, kind): the same names recur in every rule of a set."""

    def __init__(self, elements: Iterable[ScopeElement]) -> None:
        self.elements = tuple(elements)
        self._by_element: dict[str, list[ScopeElement]] = {}
        self._members: dict[MemberKind, dict[str, list[Target]]] = {
            "attribute": {},
            "operation": {},
        }
        self._answers: dict[tuple[str, MemberKind], Resolution] = {}
        for element in self.elements:
            self._by_element.setdefault(element.name, []).append(element)
            if element.short and element.short != element.name:
                self._by_element.setdefault(element.short, []).append(element)
            for kind, members in (
                ("attribute", element.attributes),
                ("operation", element.operations),
            ):
                for member, payload in members.items():
                    self._members[kind].setdefault(member, []).append(  # type: ignore[index]
                        Target(element, member, payload, kind)  # type: ignore[arg-type]
                    )

    def names(self) -> list[str]:
        """The scope's element names, in order."""
        return [e.name for e in self.elements]

    def members(self, kind: MemberKind) -> list[str]:
        """Every attribute (or operation) name of the scope."""
        return list(self._members[kind])

    def resolve(self, written: str, kind: MemberKind) -> Resolution:
        """What ``written`` denotes among the scope's attributes (``kind`` "attribute") or
        operations."""
        key = (written, kind)
        answer = self._answers.get(key)
        if answer is None:
            answer = self._answers[key] = self._resolve(written, kind)
        return answer

    def _resolve(self, written: str, kind: MemberKind) -> Resolution:
        qualifier, dot, member = written.rpartition(".")
        found = self._members[kind].get(member, [])
        if dot:
            owners = self._by_element.get(qualifier)
            if not owners:
                return Unresolved(member, qualifier, (), ())
            matching = [t for t in found if t.element in owners]
            if not matching:
                known = tuple(
                    m
                    for e in owners
                    for m in (e.attributes if kind == "attribute" else e.operations)
                )
                return Unresolved(member, qualifier, tuple(owners), known)
            return matching[0]
        if not found:
            return Unresolved(member, None, (), tuple(self._members[kind]))
        if len(found) > 1:
            return Ambiguous(tuple(found))
        return found[0]


# ------------------------------------------------------------------------------- a set's rules
Use = Literal["read", "write", "call", "action-read"]


def uses(rule: Rule) -> Iterator[tuple[Name, Use]]:
    """Every name a parsed rule writes, with how it uses it: ``read`` by its condition,
    ``write`` assigned or concluded by an action, ``call`` an operation an action calls,
    ``action-read`` read by an action (an assigned expression, an operation's argument).
    Conditions first, then the actions left to right."""
    for name in rule.variables_read():
        yield name, "read"
    for action in rule.actions:
        if isinstance(action, Call):
            yield action.target, "call"
            for arg in action.args:
                for name in names_in(arg):
                    yield name, "action-read"
        else:
            yield action.var, "write"
            if isinstance(action, Assign):
                for name in names_in(action.value):
                    yield name, "action-read"


@dataclass
class Binding:
    """A policy set's rules resolved in its :class:`Scope`.

    ``variables``: each attribute name as written -> its :class:`Target`; ``calls``: each
    operation name as written -> its target;
    ``inputs``: the variables (canonical ``Element.attribute``) the engine is given before each
    firing, in order of first use (a crisp engine keeps assigned values between firings, so its
    outputs are inputs too); ``outputs``: those its rules write, read back after each firing;
    ``triggers``: those its conditions read, whose change fires an event-triggered set;
    ``operations``: the operations its rules call (canonical ``Element.operation``);
    ``problems``: each name that did not resolve, with its rule, how it was used and why."""

    variables: dict[str, Target] = field(default_factory=dict)
    calls: dict[str, Target] = field(default_factory=dict)
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    triggers: tuple[str, ...] = ()
    operations: tuple[str, ...] = ()
    problems: list[tuple[Rule, Name, Use, Ambiguous | Unresolved]] = field(default_factory=list)

    def targets(self) -> dict[tuple[MemberKind, str], tuple[Target, list[str]]]:
        """Every target by (kind, canonical name), in order of first use, with the names written
        for it."""
        out: dict[tuple[MemberKind, str], tuple[Target, list[str]]] = {}
        for written, target in (*self.variables.items(), *self.calls.items()):
            out.setdefault((target.kind, target.name), (target, []))[1].append(written)
        return out


def bind(
    scope: Scope,
    rules: Iterable[Rule],
    kind: RuleKind,
    *,
    aliases: Mapping[str, str] | None = None,
) -> Binding:
    """Resolve every name of ``rules`` (a policy set's, in order) in ``scope``; see
    :class:`Binding`. ``aliases`` binds names by hand (written name -> ``Element.member``, resolved
    instead). Unresolved names are listed in ``problems``, never raised."""
    aliases = aliases or {}
    found = Binding()
    reads: dict[str, None] = {}
    writes: dict[str, None] = {}
    calls: dict[str, None] = {}
    action_reads: dict[str, None] = {}
    order = {"read": reads, "write": writes, "call": calls, "action-read": action_reads}
    for rule in rules:
        for name, use in uses(rule):
            written = aliases.get(name.text, name.text)
            answer = scope.resolve(written, "operation" if use == "call" else "attribute")
            if not isinstance(answer, Target):
                found.problems.append((rule, name, use, answer))
                continue
            (found.calls if use == "call" else found.variables).setdefault(name.text, answer)
            order[use].setdefault(answer.name, None)
    inputs = dict(reads)
    inputs.update(dict.fromkeys(action_reads))
    if kind == "crisp":
        inputs.update(dict.fromkeys(writes))
    found.inputs = tuple(inputs)
    found.outputs = tuple(writes)
    found.triggers = tuple(reads)
    found.operations = tuple(calls)
    return found


DEFAULT_LABEL = "rule{}"
"""An unlabelled rule's label: ``rule<n>``, n its 1-based position among its policy's rules (the
first such label not taken), as the engines label a rule given without one."""


def default_label(position: int, taken: Iterable[str]) -> str:
    """The label of the unlabelled rule at 1-based ``position``, not among ``taken``."""
    used = set(taken)
    n = position
    while DEFAULT_LABEL.format(n) in used:
        n += 1
    return DEFAULT_LABEL.format(n)
