"""What a reference to an id the file does not have costs the architecture, and so which later
findings the reader's finding about it explains (:mod:`acordcs.model.causes`).

- R202 on a relation (a dependency's client or supplier, an association's end or its type): the
  relation is lost. What the role at its other end then lacks is explained by it, and, when the
  id is a misspelling of one role's id (or name) that such a relation could join and that lacks
  it, what that role lacks too: a component the misspelt deployment does not host (A506), the
  rules naming it out of the scope of a set whose ``adapts`` is misspelt (L402).
- R204 (a stereotype applied to an id no element has): the element whose id it misspells plays
  no role; what rules name of it is explained by it.
- R201 as an error (a stereotype on an element of an unknown type): likewise.

Only errors explain (a warning R202 touches no ACORD-CS element), and the guess of a misspelt id
needs one closest candidate: ids a digit apart (BOUML's counters) with several candidates guess
nothing.
"""

from __future__ import annotations

from collections import defaultdict

from acordcs.diagnostics import Diagnostic, Severity, within_edits
from acordcs.model import causes
from acordcs.model.architecture import STEREOTYPES, Architecture, Role, relation_between
from acordcs.xmi.uml import Classifier, Element, Property

# Relations whose target has at most one source: a role that has one is no candidate for a lost one.
_ONE_SOURCE = {"hosts", "owns_port", "contains"}
_STEREOTYPED_KINDS = {"Class", "Component", "AssociationClass", "Port", "Property"}
_MIN_GUESSED = 4  # ids shorter than this are within two edits of too much


def explain_lost_references(arch: Architecture) -> None:
    """Give the reader's R201, R202 and R204 errors the keys of the findings they explain (and
    record in ``arch.misapplied`` the elements an R204 leaves without their stereotype)."""
    uml = arch.uml
    found: dict[tuple[str, str], list[Diagnostic]] = defaultdict(list)
    for d in uml.diagnostics:
        if d.severity is Severity.ERROR and d.xmi_id and d.code in ("R201", "R202", "R204"):
            found[(d.code, d.xmi_id)].append(d)
    if not found:
        return
    for (code, ident), diags in found.items():
        if code == "R201" and ident in arch.misapplied:
            _explain(diags, (causes.unread(ident),))
        elif code == "R204":
            meant = _meant_element(arch, ident)
            if meant is not None:
                arch.misapplied.setdefault(meant.id, meant)
                _explain(diags, (causes.unread(meant.id),))
                _did_you_mean(diags, "which no element has", meant, None)
    for dep in uml.dependencies:
        for ident, client in [(i, True) for i in dep.clients] + [(i, False) for i in dep.suppliers]:
            diags = [d for d in found.get(("R202", ident), []) if d.element == dep.qualified_name()]
            if not diags or ident in uml.elements:
                continue
            others = dep.suppliers if client else dep.clients
            keys: list[str] = []
            for other in others:
                if other in arch.roles:
                    keys += _lost(arch, diags, ident, arch.roles[other], known_first=not client)
            _explain(diags, tuple(keys))
    for assoc in uml.associations:
        ends = [
            e for e in (uml.elements.get(i) for i in assoc.member_ends) if isinstance(e, Property)
        ]
        lost = [(i, assoc.qualified_name()) for i in assoc.member_ends if i not in uml.elements]
        lost += [(e.type_ref, e.qualified_name()) for e in ends if e.type_ref]
        own = arch.roles.get(assoc.id)  # an AssociationClass playing a role: from it to its ends
        known = (
            [own]
            if own is not None
            else _distinct(
                [arch.roles[e.type_ref] for e in ends if e.type_ref in arch.roles]
                + [
                    arch.roles[e.owner.id]
                    for e in ends
                    if isinstance(e.owner, Classifier)
                    and e.owner is not assoc
                    and e.owner.id in arch.roles
                ]
            )
        )
        for ident, where in lost:
            if ident in uml.elements:
                continue
            diags = [d for d in found.get(("R202", ident), []) if d.element == where]
            keys = []
            for role in known:
                keys += _lost(arch, diags, ident, role, known_first=True, directed=own is not None)
            _explain(diags, tuple(keys))


def _explain(diags: list[Diagnostic], keys: tuple[str, ...]) -> None:
    for d in diags:
        d.explains = tuple(dict.fromkeys((*d.explains, *keys)))


def _did_you_mean(diags: list[Diagnostic], after: str, element: Element, kind: str | None) -> None:
    """Say in each of ``diags``, after the words ``after``, which element the missing id misspells."""
    what = f"<<{kind}>> {element.name!r}" if kind else f"{element.kind} {element.name!r}"
    told = f" (did you mean {element.id!r}, {what}?)"
    for d in diags:
        if told not in d.message:
            at = d.message.find(after)
            d.message = (
                d.message[: at + len(after)] + told + d.message[at + len(after) :]
                if at >= 0
                else d.message + told
            )


def _distinct(roles: list[Role]) -> list[Role]:
    return list({r.id: r for r in roles}.values())


def _side(first_is_source: bool, known_first: bool) -> str:
    return causes.SOURCE if first_is_source == known_first else causes.TARGET


def _lost(
    arch: Architecture,
    diags: list[Diagnostic],
    ident: str,
    known: Role,
    *,
    known_first: bool,
    directed: bool = True,
) -> list[str]:
    """The keys a relation between ``known`` and the missing ``ident`` explains; ``known_first``:
    ``known`` is the relation's first element (a dependency's client)."""
    possible: list[tuple[str, str, str]] = []  # (relation, the known role's side, other's kind)
    for kind in STEREOTYPES:
        pair = (known.kind, kind) if known_first else (kind, known.kind)
        found = relation_between(*pair, directed=directed)
        if found is not None:
            possible.append((found[0], _side(found[1], known_first), kind))
    meant = _meant_role(arch, ident, known, possible)
    if meant is not None:
        role, relation, side = meant
        other = causes.TARGET if side == causes.SOURCE else causes.SOURCE
        source, target = (known, role) if side == causes.SOURCE else (role, known)
        _did_you_mean(diags, "which no element of the file has", role.element, role.kind)
        return [
            causes.pair(relation, source.id, target.id),
            causes.lacks(relation, known.id, side),
            causes.lacks(relation, role.id, other),
        ]
    keys = []
    for relation, side, _ in possible:
        keys += [causes.lacks(relation, known.id, side), causes.maybe(relation, known.id, side)]
    return keys


def _meant_role(
    arch: Architecture, ident: str, known: Role, possible: list[tuple[str, str, str]]
) -> tuple[Role, str, str] | None:
    """The role the missing ``ident`` misspells, with the relation it would have with ``known``
    and ``known``'s side: the closest (two edits at most) of the roles such a relation could
    join that are not so related already; None unless exactly one is closest."""
    by_kind = {kind: (relation, side) for relation, side, kind in possible}
    scored: list[tuple[int, Role, str, str]] = []
    for role in arch.roles.values():
        if role is known or role.kind not in by_kind:
            continue
        relation, side = by_kind[role.kind]
        if side == causes.SOURCE:
            taken = role in arch.related(known, relation)
            full = relation in _ONE_SOURCE and bool(arch.related_to(role, relation))
        else:
            taken = known in arch.related(role, relation)
            full = False
        if taken or full:
            continue
        distance = _distance(ident, role.element)
        if distance is not None:
            scored.append((distance, role, relation, side))
    return _unique_closest(scored)


def _meant_element(arch: Architecture, ident: str) -> Element | None:
    """The element playing no role whose id (or name) the missing ``ident`` misspells."""
    scored = []
    for element in arch.uml.elements.values():
        if element.id in arch.roles or element.kind not in _STEREOTYPED_KINDS:
            continue
        distance = _distance(ident, element)
        if distance is not None:
            scored.append((distance, element))
    scored.sort(key=lambda s: s[0])
    if not scored or (len(scored) > 1 and scored[1][0] == scored[0][0]):
        return None
    return scored[0][1]


def _unique_closest(scored: list) -> tuple | None:
    scored.sort(key=lambda s: s[0])
    if not scored or (len(scored) > 1 and scored[1][0] == scored[0][0]):
        return None
    return tuple(scored[0][1:])


def _distance(ident: str, element: Element) -> int | None:
    """Edits (at most two) from ``ident`` to ``element``'s id, or to its name (an id written as
    the name, ``_Fan`` for ``Fan``); None when further."""
    if len(ident) < _MIN_GUESSED:
        return None
    bare = ident.lstrip("_")
    for limit in (0, 1, 2):
        if within_edits(ident, element.id, limit) or (
            element.name and within_edits(bare, element.name, limit)
        ):
            return limit
    return None
