"""One (path, value) entry of the subscription index: every operator's thresholds, kept sorted."""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from typing import Any

Entry = Any  # the index stores any hashable subscription object


def _insert(keys: list, subs: list, key: object, sub: Entry) -> None:
    i = bisect_right(keys, key)
    keys.insert(i, key)
    subs.insert(i, sub)


def _delete(keys: list, subs: list, key: object, sub: Entry) -> None:
    i = bisect_left(keys, key)
    while subs[i] is not sub:
        i += 1
    del keys[i]
    del subs[i]


class ValueEntry:
    """All subscriptions on one (path, value) pair, whatever their operator.

    ``. > c`` holds iff ``v >= nextafter(c, +inf)`` for doubles, so ``>`` and ``>=`` share one sorted
    list answered by one bisection (``<`` and ``<=`` likewise); ``=`` is a dict lookup and ``!=`` is
    everything but that lookup. Lists are kept sorted on insertion: no rebuild after a change.
    """

    __slots__ = (
        "exists",
        "hi_keys",
        "hi_subs",
        "lo_keys",
        "lo_subs",
        "members",
        "ne",
        "ne_all",
        "num_eq",
        "num_ne",
        "numeric",
        "str_eq",
        "str_ne",
        "str_ne_all",
        "textual",
    )

    def __init__(self) -> None:
        self.members: dict[Entry, tuple] = {}
        self.exists: list = []
        self.lo_keys: list[float] = []  # value >= key
        self.lo_subs: list = []
        self.hi_keys: list[float] = []  # value <= key
        self.hi_subs: list = []
        self.num_eq: dict[float, list] = {}
        self.num_ne: dict[float, list] = {}
        self.ne_all: list = []
        self.str_eq: dict[str, list] = {}
        self.str_ne: dict[str, list] = {}
        self.str_ne_all: list = []
        self.numeric = False  # does any subscription compare numbers / strings?
        self.textual = False

    def _refresh(self) -> None:
        self.numeric = bool(self.lo_keys or self.hi_keys or self.num_eq or self.ne_all)
        self.textual = bool(self.str_eq or self.str_ne_all)

    def _place(self, op: str | None, kind: str | None, const: object) -> tuple[str, object] | None:
        """Where a subscription goes: (slot, key), or None if it can never match."""
        if op is None:
            return ("exists", None)
        if kind == "str":
            return ("str_eq" if op == "=" else "str_ne", const)
        if const != const:  # NaN: every comparison with it is false, except !=
            return ("ne_all", None) if op == "!=" else None
        if op == "=":
            return ("num_eq", const)
        if op == "!=":
            return ("num_ne", const)
        if op == ">":
            return None if const == math.inf else ("lo", math.nextafter(const, math.inf))
        if op == ">=":
            return ("lo", const)
        if op == "<":
            return None if const == -math.inf else ("hi", math.nextafter(const, -math.inf))
        return ("hi", const)

    def add(self, sub: Entry, op: str | None, kind: str | None, const: object) -> None:
        place = self._place(op, kind, const)
        self.members[sub] = place
        if place is None:
            return
        slot, key = place
        if slot == "exists":
            self.exists.append(sub)
        elif slot == "lo":
            _insert(self.lo_keys, self.lo_subs, key, sub)
        elif slot == "hi":
            _insert(self.hi_keys, self.hi_subs, key, sub)
        elif slot == "ne_all":
            self.ne_all.append(sub)
        elif slot in ("num_eq", "str_eq"):
            getattr(self, slot).setdefault(key, []).append(sub)
        else:  # num_ne / str_ne: listed under their constant and among all
            getattr(self, slot).setdefault(key, []).append(sub)
            (self.ne_all if slot == "num_ne" else self.str_ne_all).append(sub)
        self._refresh()

    def remove(self, sub: Entry) -> None:
        place = self.members.pop(sub)
        if place is None:
            return
        slot, key = place
        if slot == "exists":
            self.exists.remove(sub)
        elif slot == "lo":
            _delete(self.lo_keys, self.lo_subs, key, sub)
        elif slot == "hi":
            _delete(self.hi_keys, self.hi_subs, key, sub)
        elif slot == "ne_all":
            self.ne_all.remove(sub)
        else:
            bucket = getattr(self, slot)
            bucket[key].remove(sub)
            if not bucket[key]:
                del bucket[key]
            if slot == "num_ne":
                self.ne_all.remove(sub)
            elif slot == "str_ne":
                self.str_ne_all.remove(sub)
        self._refresh()

    def matching(self, numbers: list | None, strings: list) -> list:
        """Subscriptions some value satisfies: ``numbers`` are number(strings), None if not needed."""
        if numbers and len(numbers) == 1 and not self.textual:
            # the common case (one node, one value, numeric constants), kept lean
            v = numbers[0]
            if v != v:
                return _unequal(numbers, self.num_ne, self.ne_all) if self.ne_all else []
            found = self.lo_subs[: bisect_right(self.lo_keys, v)] if self.lo_keys else []
            if self.hi_keys:
                found += self.hi_subs[bisect_left(self.hi_keys, v) :]
            if self.num_eq:
                found += self.num_eq.get(v, ())
            if self.ne_all:
                found += _unequal(numbers, self.num_ne, self.ne_all)
            return found
        found = []
        if numbers:
            real = [v for v in numbers if v == v]
            if real:
                top, bottom = max(real), min(real)
                if self.lo_keys:
                    found.extend(self.lo_subs[: bisect_right(self.lo_keys, top)])
                if self.hi_keys:
                    found.extend(self.hi_subs[bisect_left(self.hi_keys, bottom) :])
                if self.num_eq:
                    for v in set(real):
                        found.extend(self.num_eq.get(v, ()))
            if self.ne_all:
                found.extend(_unequal(numbers, self.num_ne, self.ne_all))
        if strings and self.textual:
            for s in set(strings):
                found.extend(self.str_eq.get(s, ()))
            if self.str_ne_all:
                found.extend(_unequal(strings, self.str_ne, self.str_ne_all))
        return found


def _unequal(values: list, buckets: dict, everyone: list) -> list:
    """Subscriptions ``value != c`` holds for with some value: all of them unless every value is the
    same (non-NaN) one, in which case all but that constant's bucket."""
    distinct = set(values)
    if len(distinct) > 1 or any(v != v for v in distinct):
        return everyone
    equal = buckets.get(next(iter(distinct)))
    if not equal:
        return everyone
    excluded = set(equal)
    return [s for s in everyone if s not in excluded]
