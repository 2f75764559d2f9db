"""What a fire sends back: the records of ``?*acord-out*`` (see :mod:`.prelude`), read from CLIPS.

A fire's result is a multifield of records in firing order. clipspy would convert it whole, each
field through its generic ``python_value``; :func:`decode` reads the C values directly (a field is
two or three cffi accesses), stores assignments in the value list as it goes and returns the calls
and anything else for the engine to deal with, in one pass.

Call sites and constant assignments of crisp rules are numbered at compile time (:class:`Sites`):
their records are one field, a negative number, which Python looks up; the compiled rule does not
send what Python already knows (the operation, the rule, the constant).
"""

from __future__ import annotations

from acordcs.engines.clips.bridge import c_string, python_value
from acordcs.engines.clips.values import Value

Call = tuple[int | str, int, list[Value]]  # operation (number or name), rule number, arguments
# Something the engine must look at: ("err", rule, message), or ("set", index, value) when a
# numeric variable got something else, or a number again (numeric mode, see ClipsEngine._track).
Note = tuple[str, int, Value]

_SYMBOLS: dict[str, Value] = {"TRUE": True, "FALSE": False, "nil": None}


class Sites:
    """Numbered places of compiled rules that record something, by the number in their records.

    An entry is ``(op, rule, nargs)`` for a call of operation number ``op`` (>= 1) by rule number
    ``rule``, or ``(0, index, value)`` for the assignment of a constant to variable ``index``.
    """

    def __init__(self) -> None:
        self.entries: list[tuple[int, int, object]] = [(0, 0, None)]

    def call(self, op: int, rule: int, nargs: int) -> int:
        self.entries.append((op, rule, nargs))
        return len(self.entries) - 1

    def constant(self, index: int, value: Value) -> int:
        self.entries.append((0, index, value))
        return len(self.entries) - 1


def python_constant(value: int | float | str | bool) -> Value:
    """The value CLIPS holds for a literal of a rule (compiler.constant: big integers are reals)."""
    if isinstance(value, bool | str):
        return value
    if isinstance(value, int) and abs(value) < 2**63:
        return value
    return float(value)


def read_value(item: object, ptr: object) -> Value:
    """One field as a rule value: TRUE/FALSE are booleans, nil is unset, other symbols are text."""
    kind = item.header.type  # type codes as numbers: bridge.py checks them at import
    if kind == 0:
        return item.floatValue.contents
    if kind == 1:
        return item.integerValue.contents
    if kind == 2:
        text = c_string(item.lexemeValue.contents).decode()
        return _SYMBOLS.get(text, text)
    if kind == 3:
        return c_string(item.lexemeValue.contents).decode()
    return python_value(ptr, item)  # not a rule value (a native rule's fact address...): as clipspy


def decode(
    multifield: object,
    ptr: object,
    sites: list[tuple[int, int, object]],
    values: list[Value],
    numeric: set[int],
    odd: set[int],
) -> tuple[list[Call] | None, list[Note] | None]:
    """Apply the records of ``multifield`` (a ``struct multifield *``) to ``values``; return the
    calls and the notes, in firing order (None when there are none: the usual case).

    ``numeric``: the variables declared as numbers; the engine hears of (``"set"`` note) those
    given something else than a number, and of those ``odd`` (not holding a number) given one.
    """
    calls: list[Call] | None = None
    notes: list[Note] | None = None
    base, n, i = multifield.contents, multifield.length, 0
    last_site, last_index = len(sites), len(values)
    while i < n:  # each check fails only on records a native rule wrote into ?*acord-out*
        item = base + i
        if item.header.type == 1:  # an integer tag: crisp rules' records, acord-assign's
            tag = item.integerValue.contents
            if -last_site < tag < 0:  # a site: (op, rule, nargs) calls, (0, index, value) assigns
                op, index, value = sites[-tag]
                if op:
                    if i + 1 + value > n:
                        break
                    args = [read_value(base + k, ptr) for k in range(i + 1, i + 1 + value)]
                    i += 1 + value
                    if calls is None:
                        calls = []
                    calls.append((op, index, args))
                    continue
                i += 1
            elif 0 < tag < last_index and i + 1 < n:  # index value
                index = tag
                item = base + (i + 1)
                kind = item.header.type  # inline for the usual numbers: a call less
                if kind == 0:
                    value = item.floatValue.contents
                elif kind == 1:
                    value = item.integerValue.contents
                else:
                    value = read_value(item, ptr)
                i += 2
            else:
                break
            values[index] = value
            if index in numeric and (
                (type(value) is not float and type(value) is not int) or index in odd
            ):
                if notes is None:
                    notes = []
                notes.append(("set", index, value))
            continue
        head = read_value(item, ptr)
        if head == "err" and i + 2 < n:  # err rule message
            rule = read_value(base + (i + 1), ptr)
            if notes is None:
                notes = []
            notes.append(("err", rule, read_value(base + (i + 2), ptr)))  # type: ignore[arg-type]
            i += 3
            continue
        if head == "op" and i + 2 < n:  # op name nargs args...: a native rule's call by name
            count = read_value(base + (i + 2), ptr)
            if type(count) is int and i + 3 + count <= n:
                args = [read_value(base + k, ptr) for k in range(i + 3, i + 3 + count)]
                if calls is None:
                    calls = []
                calls.append((str(read_value(base + (i + 1), ptr)), 0, args))
                i += 3 + count
                continue
        break
    if i < n:  # unreadable: report it, and read no further
        what = read_value(base + i, ptr)
        message = f"unreadable record {what!r} from CLIPS; did a native rule bind ?*acord-out*?"
        notes = [*(notes or ()), ("err", 0, message)]
    return calls, notes
