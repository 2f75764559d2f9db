"""How a plan line (:mod:`acordcs.descriptor.diff`) writes what changes: values, rule texts with
the words both versions share left out, names, frequencies, operations."""

from __future__ import annotations

from collections.abc import Iterable

from acordcs.descriptor.application import Operation


def shown(value: object) -> str:
    """A default as a plan line shows it: numbers as written (``200``, ``0.5``), text quoted."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}" if value == float(f"{value:g}") else repr(value)
    if isinstance(value, int):
        return str(value)
    if value is None:
        return "(none)"
    return repr(str(value))


def elided(old: str, new: str) -> str:
    """``old -> new`` with the words both start and end with left out (``...``), keeping one
    word of context before the first difference: ``... is slow -> ... is fast``."""
    a, b = old.split(" "), new.split(" ")
    head = 0
    while head < min(len(a), len(b)) and a[head] == b[head]:
        head += 1
    tail = 0
    while tail < min(len(a), len(b)) - head and a[-1 - tail] == b[-1 - tail]:
        tail += 1
    keep = max(head - 1, 0)
    if keep < 2:  # too little in common to be worth leaving out
        keep = 0
    left = "... " if keep else ""
    right = " ..." if tail > 1 else ""
    tail = tail if tail > 1 else 0
    mid_a = " ".join(a[keep : len(a) - tail])
    mid_b = " ".join(b[keep : len(b) - tail])
    return f"{left}{mid_a}{right} -> {left}{mid_b}{right}"


def names(items: Iterable[object]) -> str:
    listed = [getattr(i, "name", str(i)) for i in items]
    return ", ".join(listed) if listed else "(none)"


def hz(value: float | None) -> str:
    return "(none)" if value is None else f"{shown(value)} Hz"


def signature(op: Operation) -> str:
    params = ", ".join(
        (f"{p.direction} " if p.direction != "in" else "") + f"{p.name}: {p.type or '?'}"
        for p in op.parameters
    )
    return f"{op.name}({params})" + (f": {op.return_type}" if op.return_type else "")
