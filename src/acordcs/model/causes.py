"""Causes first, consequences once: a finding that another reported finding explains is not
printed on its own; the cause says how many it stands for and what they are about.

A finding names what would explain it by keys (:attr:`Diagnostic.because`), and a cause the keys
it explains (:attr:`Diagnostic.explains`). The keys say what is missing, never how it is worded:

- :func:`unread`: an element whose ACORD-CS stereotype was not read (misspelt, T302; on the wrong
  metaclass, T301; on an element of an unknown type, R201; applied to an id no element has,
  R204), so that it plays no role: a rule naming it or one of its members does not resolve (L402,
  L406), a port it owns belongs to no component (A511, A517).
- :func:`variable_of`: a ``<<CtxVariable>>`` applied to a classifier (or to a member other than an
  attribute) instead of to an attribute of it: the rules using that attribute as a linguistic
  variable (L408).
- :func:`lacks`, :func:`maybe`, :func:`pair`: a relation lost with a reference to an id the file
  does not have (R202): what the role it would have joined then lacks (A505, A506, A508, A509,
  A511, A513, A514, A517), and a rule's name that the relation would have put in a policy set's
  scope (L402, L406).

A cause hides a finding only when it is at least as severe (an error never hides behind a
warning, so the exit code stays what the findings make it); a finding with no reported cause is
printed as it always was.
"""

from __future__ import annotations

import dataclasses
from collections import defaultdict

from acordcs.diagnostics import Diagnostic, shorten

SOURCE, TARGET = "source", "target"


def unread(element_id: str) -> str:
    """The element ``element_id`` plays no role: its ACORD-CS stereotype was not read."""
    return f"unread:{element_id}"


def variable_of(classifier_id: str) -> str:
    """A ``<<CtxVariable>>`` meant for an attribute of ``classifier_id`` was applied elsewhere."""
    return f"variable:{classifier_id}"


def lacks(relation: str, role_id: str, side: str) -> str:
    """The role ``role_id`` has no ``relation`` in which it is the ``side`` (:data:`SOURCE`, the
    container hosting, the monitor feeding...; or :data:`TARGET`)."""
    return f"lacks:{relation}:{side}:{role_id}"


def maybe(relation: str, role_id: str, side: str) -> str:
    """A ``relation`` of ``role_id`` (at ``side``) with an element unknown would explain the
    finding: what a rule names is out of scope, and the lost relation might have put it in."""
    return f"maybe:{relation}:{side}:{role_id}"


def pair(relation: str, source_id: str, target_id: str) -> str:
    """The ``relation`` from ``source_id`` to ``target_id`` would explain the finding."""
    return f"pair:{relation}:{source_id}:{target_id}"


# What a finding's code is about, from reading the file to generating code: a finding of an
# earlier stage about an element can cause findings of later stages about it, never the reverse.
_STAGES = {letter: n for n, letter in enumerate("XRTNLAGZ")}

_SHOWN_SUBJECTS = 3


def settled(found: list[Diagnostic]) -> list[Diagnostic]:
    """``found`` with every finding a reported cause explains folded into that cause (its message
    saying how many it stands for), in reading order (:func:`in_reading_order`); a consequence a
    cause cannot hide (more severe than the cause) is printed right after it."""
    ordered = in_reading_order(found)
    causes: dict[str, Diagnostic] = {}
    for d in ordered:  # the first cause in reading order explains a key: deterministic
        for key in d.explains:
            causes.setdefault(key, d)
    if not causes:
        return ordered
    hidden: dict[int, list[Diagnostic]] = defaultdict(list)
    anchors: dict[int, Diagnostic] = {}
    kept: list[Diagnostic] = []
    for d in ordered:
        cause = _root_cause(d, causes)
        if cause is None:
            kept.append(d)
        elif cause.severity >= d.severity:
            hidden[id(cause)].append(d)
        else:
            anchors[id(d)] = cause
            kept.append(d)
    out = [_standing_for(d, hidden[id(d)]) if hidden.get(id(d)) else d for d in kept]
    if not anchors:
        return out
    # A cause's message changed, not its position: the same objects' keys, by identity.
    replaced = {id(old): new for old, new in zip(kept, out, strict=True)}
    return in_reading_order(
        out, {id(replaced[k]): replaced[id(c)] for k, c in anchors.items() if id(c) in replaced}
    )


def _root_cause(d: Diagnostic, causes: dict[str, Diagnostic]) -> Diagnostic | None:
    """The reported cause at the end of ``d``'s chain of causes; None when there is none, or when
    the chain comes back to a finding it passed (nothing hides in a circle)."""
    seen = {id(d)}
    current, cause = d, None
    while True:
        following = next(
            (causes[k] for k in current.because if k in causes and causes[k] is not current), None
        )
        if following is None:
            return cause
        if id(following) in seen:
            return None
        seen.add(id(following))
        current = cause = following


def _about(d: Diagnostic) -> str:
    """What a hidden finding is about, for its cause's message: a rule's name as written, else
    the element's own name."""
    if d.code.startswith("L") and d.subject and ":" in d.subject:
        return d.subject.rpartition(":")[2]
    if d.element:
        return d.element.rpartition("::")[2]
    return d.xmi_id or d.code


def _standing_for(cause: Diagnostic, hidden: list[Diagnostic]) -> Diagnostic:
    subjects = list(dict.fromkeys(_about(d) for d in hidden))
    shown = ", ".join(repr(s) for s in subjects[:_SHOWN_SUBJECTS])
    if len(subjects) > _SHOWN_SUBJECTS:
        shown += f" and {len(subjects) - _SHOWN_SUBJECTS} more"
    codes = ", ".join(sorted({d.code for d in hidden}))
    n = len(hidden)
    told = (
        f"; {n} finding{'s' if n != 1 else ''} ({codes}) about {shown} "
        f"{'are' if n != 1 else 'is'} checked once this is fixed"
    )
    return dataclasses.replace(cause, message=cause.message + shorten(told))


def in_reading_order(
    found: list[Diagnostic], anchors: dict[int, Diagnostic] | None = None
) -> list[Diagnostic]:
    """``found`` by source position, causes before consequences: the findings about one element
    together, where its first one is in the file, in the order of their stages (a misspelt tag
    of a monitor, at the stereotype application near the file's end, before what the monitor
    then lacks, at the monitor itself), then by line and column. ``anchors`` (a finding's id ->
    its cause): each such finding right after its cause, wherever it is in the file."""
    first: dict[str, int] = {}
    for d in found:
        if d.xmi_id:
            first[d.xmi_id] = min(first.get(d.xmi_id, d.line), d.line)

    def place(d: Diagnostic) -> tuple:
        where = first.get(d.xmi_id, d.line) if d.xmi_id else d.line
        return (where, d.xmi_id or "", _STAGES.get(d.code[:1], 9), d.line, d.column, d.code)

    def key(d: Diagnostic) -> tuple:
        cause = anchors.get(id(d)) if anchors else None
        return (*place(cause), 1, *place(d)) if cause is not None else (*place(d), 0)

    return sorted(found, key=key)
