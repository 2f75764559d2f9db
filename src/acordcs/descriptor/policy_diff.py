"""What differs between two versions of a policy set, as the phrases of plan lines
(:mod:`acordcs.descriptor.diff`): its engine, trigger and what it adapts and is fed by, its
rules (by label), its linguistic variables and terms, what its rules read, write and fire on."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

from acordcs.descriptor.application import Policy, PolicySet, Variable
from acordcs.descriptor.formatting import elided, hz, names, shown


def policy_set_changes(
    a: PolicySet, b: PolicySet, fed: tuple[Sequence[str], Sequence[str]]
) -> list[str]:
    """What differs between policy sets ``a`` and ``b`` (``fed``: the monitors feeding each),
    one phrase of a plan line each (``rule smallNarrow: ... is slow -> ... is fast``)."""
    fed_text = (", ".join(fed[0]), ", ".join(fed[1]))
    found: list[str] = []
    for label, x, y in (
        ("engine", a.engine, b.engine),
        ("semantics", a.semantics, b.semantics),
        ("trigger", a.trigger, b.trigger),
        ("frequency", hz(a.frequency), hz(b.frequency)),
        ("adapts", names(a.adapts), names(b.adapts)),
        ("fed by", fed_text[0] or "(none)", fed_text[1] or "(none)"),
    ):
        if x != y:
            found.append(f"{label} {x} -> {y}")
    found += _rules(a, b)
    found += _variables(a.variables, b.variables)
    for label, was, now in (
        ("reads", a.inputs, b.inputs),
        ("writes", a.outputs, b.outputs),
        ("fires on", a.triggers, b.triggers),
    ):
        if was != now:
            found.append(f"{label} {', '.join(was) or '(none)'} -> {', '.join(now) or '(none)'}")
    if not found and _bound(a) != _bound(b):
        found.append("what its rules name is bound differently (types, defaults, arities)")
    return found


def _rules(a: PolicySet, b: PolicySet) -> list[str]:
    out = []
    owners: dict[str, set[str]] = {}
    for policy in (*a.policies, *b.policies):
        for r in policy.rules:
            owners.setdefault(r.label, set()).add(policy.name)

    def rule(policy: str, label: str) -> str:
        # a label is unique in its policy; the policy is named when another has it too
        return f"rule {label}" if len(owners[label]) == 1 else f"rule {policy}.{label}"

    for name, p, q in _pairs(a.policies, b.policies):
        if p is None and q is not None:
            count = len(q.rules)
            out.append(f"policy {name} added ({count} rule{'s' if count != 1 else ''})")
        elif q is None:
            out.append(f"policy {name} removed")
        elif p is not None:
            out += _policy(p, q, rule)
    return out


def _policy(p: Policy, q: Policy, rule: Callable[[str, str], str]) -> list[str]:
    out = []
    before = {r.label: r for r in p.rules}
    after = {r.label: r for r in q.rules}
    for label, r in before.items():
        s = after.get(label)
        if s is None:
            out.append(f"{rule(p.name, label)} removed")
            continue
        if r.text != s.text:
            out.append(f"{rule(p.name, label)}: {elided(r.text, s.text)}")
        if r.priority != s.priority:
            out.append(f"{rule(p.name, label)}: priority {r.priority} -> {s.priority}")
    for label, s in after.items():
        if label not in before:
            out.append(f"{rule(p.name, label)} added: {s.text}")
    return out


def _variables(old: Sequence[Variable], new: Sequence[Variable]) -> list[str]:
    out = []
    before = {v.name: v for v in old}
    after = {v.name: v for v in new}
    for name, v in before.items():
        w = after.get(name)
        if w is None:
            out.append(f"variable {name} removed")
            continue
        if (v.minimum, v.maximum) != (w.minimum, w.maximum):
            out.append(
                f"variable {name}: range {shown(v.minimum)}..{shown(v.maximum)} -> "
                f"{shown(w.minimum)}..{shown(w.maximum)}"
            )
        terms_before = {t.name: t for t in v.terms}
        terms_after = {t.name: t for t in w.terms}
        for term, t in terms_before.items():
            u = terms_after.get(term)
            if u is None:
                out.append(f"variable {name}: term {term} removed")
            elif t.fcl != u.fcl:
                out.append(f"variable {name}: term {term}: {t.fcl} -> {u.fcl}")
        for term, u in terms_after.items():
            if term not in terms_before:
                out.append(f"variable {name}: term {term} added: {u.fcl}")
    for name, w in after.items():
        if name not in before:
            out.append(f"variable {name} added: {w.terms_text}")
    return out


def _bound(ps: PolicySet) -> list[tuple[object, ...]]:
    """What the set's rules name, as bound, without the ids (which say nothing that runs)."""
    return [
        (b.kind, b.element, b.member, b.names, b.value_kind, b.type, b.default, b.arity)
        for b in ps.bound
    ]


def _pairs(
    old: Sequence[Policy], new: Sequence[Policy]
) -> Iterator[tuple[str, Policy | None, Policy | None]]:
    before = {p.name: p for p in old}
    after = {p.name: p for p in new}
    for name, p in before.items():
        yield name, p, after.get(name)
    for name, q in after.items():
        if name not in before:
            yield name, None, q
