"""A container's ``--run COMPONENT.OPERATION(ARGUMENTS)``: the call written on the command line,
read without evaluating anything, and its arguments typed by the model's parameters.

:func:`parse_run` reads the text (the launcher's ``--run`` option type): ``Display.watch`` or
``Display.watch(5)``, ``Display.show('a, b', 2.5, true)``, ``Display.watch(seconds=5)``. Each
argument is one literal: a number (``5``, ``-3``, ``2.5``, ``1e-3``), ``true`` or ``false`` (any
case), or a string in single or double quotes with Python's backslash escapes; keyword arguments
name a parameter. Nothing else is read (no name, no expression, no call: nothing is evaluated), and
the text is bounded (:data:`MAX_TEXT` characters, :data:`MAX_NUMBER` per number,
:data:`MAX_ARGUMENTS` arguments), so that a hostile command line costs nothing to refuse.

:func:`bind_run` then types the arguments by the operation's parameters in the descriptor (its
``in`` and ``inout`` parameters, in order: the Python signature of the operation), as the
descriptor's value kinds read a UML type (:func:`acordcs.typed_values.value_kind`): an ``int``
takes a whole number (at most 19 characters, as the descriptor's integers), a ``double`` any
finite number, a ``bool`` ``true`` or ``false``, a ``string`` a quoted string; a parameter
without a type takes the literal as it is; one of another type (a class of the model) cannot be
given on a command line. Too many or too few arguments, a keyword naming no parameter or one
given twice, a value of the wrong kind: :class:`RunError`, saying what, which parameter, its
type and what to write. Both happen before the container starts (exit 2).
"""

from __future__ import annotations

import ast
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from acordcs.typed_values import Value, value_kind

if TYPE_CHECKING:
    from acordcs.descriptor.application import Operation

MAX_TEXT = 4096
"""Characters of one ``--run`` at most."""
MAX_NUMBER = 40
"""Characters of one number at most (an ``int``: 19, as the descriptor's integers)."""
MAX_ARGUMENTS = 64
"""Arguments of one ``--run`` at most."""

_HEAD = re.compile(r"\s*([^\s.()]+)\.([^\s.()]+)\s*")
_INTEGER = re.compile(r"[+-]?[0-9]+")
_REAL = re.compile(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?")
_NUMERIC = re.compile(r"[+-]?[0-9.]+([eE][+-]?[0-9]*)?")
_SPECIAL = re.compile(r"[+-]?(nan|inf|infinity)", re.I)
_KEYWORD = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*=(?!=)")
_WRITE = {
    "int": "a whole number (5, -3)",
    "double": "a finite number (2.5, -1e3, 5)",
    "bool": "true or false",
    "string": "a string in quotes ('text' or \"text\")",
}


class RunError(ValueError):
    """A ``--run`` that cannot be read or typed: what is wrong, where, and what to write."""


@dataclass(frozen=True)
class Literal:
    """One argument as written: its ``text``, the parameter it names (``keyword``, empty: by
    position), and what it reads as (``kind``: ``int``, ``double``, ``bool`` or ``string``, and
    ``value``; ``kind`` empty: no literal, ``value`` None)."""

    text: str
    keyword: str = ""
    kind: str = ""
    value: Value | None = None


@dataclass(frozen=True)
class RunCall:
    """A ``--run`` as read: the component, the operation, the arguments as written (``None``: no
    parentheses), and after :func:`bind_run` the ``values`` in the parameters' order."""

    component: str
    operation: str
    arguments: tuple[Literal, ...] | None = None
    values: tuple[Value, ...] = ()

    @property
    def text(self) -> str:
        """The call with its values as the container passes them: ``Display.watch(5)``."""
        return f"{self.component}.{self.operation}({', '.join(map(shown, self.values))})"

    @property
    def written(self) -> str:
        """The call as written (its arguments' texts): what messages name."""
        if self.arguments is None:
            return f"{self.component}.{self.operation}"
        inner = ", ".join(
            (f"{a.keyword}={a.text}" if a.keyword else a.text) for a in self.arguments
        )
        return f"{self.component}.{self.operation}({inner})"


def shown(value: Value) -> str:
    """A value as a call shows it: ``true``, ``5``, ``2.5``, ``'text'``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value)


def parse_run(text: str) -> RunCall:
    """``text`` read as ``COMPONENT.OPERATION`` or ``COMPONENT.OPERATION(ARGUMENTS)`` (see the
    module docstring); :class:`RunError` says what is wrong."""
    if len(text) > MAX_TEXT:
        raise RunError(f"{_short(text)}: {len(text)} characters: a --run has at most {MAX_TEXT}")
    head = _HEAD.match(text)
    if head is None:
        raise RunError(
            f"{_short(text)} is not COMPONENT.OPERATION or COMPONENT.OPERATION(ARGUMENTS)"
        )
    component, operation = head.group(1), head.group(2)
    rest = text[head.end() :]
    if not rest:
        return RunCall(component, operation)
    if not rest.startswith("("):
        raise RunError(
            f"{_short(text)} is not COMPONENT.OPERATION or COMPONENT.OPERATION(ARGUMENTS): "
            f"{_short(rest)} after {component}.{operation}"
        )
    return RunCall(component, operation, _arguments(text, rest[1:]))


def _arguments(text: str, rest: str) -> tuple[Literal, ...]:
    """The arguments in ``rest`` (what follows the opening parenthesis of ``text``)."""
    out: list[Literal] = []
    i = 0
    n = len(rest)
    while True:
        i = _blanks(rest, i)
        if i < n and rest[i] == ")" and not out:
            i += 1
            break
        if len(out) == MAX_ARGUMENTS:
            raise RunError(f"{_short(text)}: more than {MAX_ARGUMENTS} arguments")
        keyword = ""
        named = _KEYWORD.match(rest, i)
        if named:
            keyword = named.group(1)
            i = _blanks(rest, named.end())
        start = i
        if i < n and rest[i] in "'\"":
            i = _string_end(text, rest, i)
        else:
            while i < n and rest[i] not in ",)([]{}'\"" and not rest[i].isspace():
                i += 1
        literal = rest[start:i]
        if not literal and i < n and rest[i] not in ",)":
            raise RunError(
                f"{_short(text)}: {_short(rest[start:].rstrip(')'))} is not a value: write a "
                "number, true or false, or a string in quotes (nothing is evaluated)"
            )
        if not literal:
            where = "the end" if i >= n else repr(rest[i])
            raise RunError(
                f"{_short(text)}: an argument is missing before {where}: write a "
                "value (a number, true or false, a string in quotes) between the commas"
            )
        out.append(_literal(text, literal, keyword))
        i = _blanks(rest, i)
        if i >= n:
            raise RunError(
                f"{_short(text)}: no ')' at the end: close the arguments (in "
                "ACORDCS_<Container>_RUN, operations are blank-separated: write the arguments "
                "without blanks, Display.show(1,2), or give the call to <Container>-start as "
                "--run '...')"
            )
        if rest[i] == ")":
            i += 1
            break
        if rest[i] != ",":
            raise RunError(
                f"{_short(text)}: {_short(rest[start:].rstrip(')'))} is not a value: write a "
                "number, true or false, or a string in quotes (nothing is evaluated)"
            )
        i += 1
    if rest[i:].strip():
        raise RunError(f"{_short(text)}: {_short(rest[i:])} after the closing ')'")
    by_name = False
    for a in out:
        by_name = by_name or bool(a.keyword)
        if by_name and not a.keyword:
            raise RunError(
                f"{_short(text)}: an argument by position after one by name: give the "
                "arguments by position first"
            )
    return tuple(out)


def _blanks(text: str, i: int) -> int:
    while i < len(text) and text[i].isspace():
        i += 1
    return i


def _string_end(text: str, rest: str, i: int) -> int:
    """The index after the string literal starting at ``rest[i]`` (a quote)."""
    quote = rest[i]
    j = i + 1
    while j < len(rest):
        if rest[j] == "\\":
            j += 2
            continue
        if rest[j] == quote:
            return j + 1
        j += 1
    raise RunError(f"{_short(text)}: a string is not closed: end it with {quote}")


def _literal(text: str, literal: str, keyword: str) -> Literal:
    """``literal`` read (never evaluated: a string through :func:`ast.literal_eval` of that
    one string literal alone)."""
    if literal[0] in "'\"":
        try:
            value = ast.literal_eval(literal)
        except (ValueError, SyntaxError) as err:
            raise RunError(f"{_short(text)}: the string {_short(literal)}: {err}") from None
        if not isinstance(value, str):  # not reached: a literal starting with a quote
            raise RunError(f"{_short(text)}: {_short(literal)} is not a string")
        return Literal(literal, keyword, "string", value)
    if literal.lower() in ("true", "false"):
        return Literal(literal, keyword, "bool", literal.lower() == "true")
    if len(literal) > MAX_NUMBER and _NUMERIC.fullmatch(literal):
        return Literal(_cut(literal), keyword, "long number")
    if _INTEGER.fullmatch(literal):
        return Literal(literal, keyword, "int", int(literal))
    if _REAL.fullmatch(literal):
        return Literal(literal, keyword, "double", float(literal))
    if _SPECIAL.fullmatch(literal):
        return Literal(literal, keyword, "not finite")
    return Literal(_cut(literal), keyword)


def bind_run(call: RunCall, operation: Operation | None) -> RunCall:
    """``call`` with its arguments typed by ``operation``'s ``in`` and ``inout`` parameters (the
    model's; None: an operation the model does not declare, whose arguments are taken as
    written); :class:`RunError` says what does not fit."""
    given = call.arguments or ()
    if operation is None:
        for a in given:
            _check_literal(call, a, "", "", 0)
        if any(a.keyword for a in given):
            raise RunError(
                f"--run {call.written}: the model declares no operation {call.operation} of "
                f"{call.component}, so its parameters have no names: give the arguments by "
                "position"
            )
        values = tuple(a.value for a in given if a.value is not None)
        return RunCall(call.component, call.operation, call.arguments, values)
    params = [p for p in operation.parameters if p.direction in ("in", "inout")]
    head = f"{call.component}.{_signature(operation.name, params)}"
    names = [p.name for p in params]
    placed: dict[str, Literal] = {}
    for position, a in enumerate(given):
        if a.keyword:
            if a.keyword not in names:
                raise RunError(
                    f"--run {call.written}: {head} has no parameter {a.keyword!r}: name one of "
                    f"{', '.join(names) or 'none (it takes no argument)'}"
                )
            if a.keyword in placed:
                raise RunError(f"--run {call.written}: parameter {a.keyword} is given twice")
            placed[a.keyword] = a
        elif position >= len(params):
            raise RunError(
                f"--run {call.written}: {head} takes {_count(len(params))}, {len(given)} "
                "given: give one value per parameter, in order"
            )
        else:
            placed[names[position]] = a
    missing = [p for p in params if p.name not in placed]
    if missing:
        listed = ", ".join(f"{p.name} ({_kind(p.type) or 'any'})" for p in missing)
        raise RunError(
            f"--run {call.written}: {head} takes {_count(len(params))}, "
            f"{len(params) - len(missing)} given: give {listed}, as {call.component}."
            f"{operation.name}({', '.join(_example(p.type) for p in params)})"
        )
    typed = [_typed(call, placed[p.name], p.name, p.type, n) for n, p in enumerate(params, 1)]
    return RunCall(call.component, call.operation, call.arguments, tuple(typed))


def _typed(call: RunCall, a: Literal, name: str, uml: str, number: int) -> Value:
    kind = _kind(uml)
    _check_literal(call, a, name, uml, number)
    what = f"argument {number} of {call.operation}, parameter {name} ({uml or 'no type'})"
    if kind is None:
        raise RunError(
            f"--run {call.written}: {what}: a value of type {uml} cannot be written on a command "
            "line (int, double, bool and string can): call the operation from your code"
        )
    value = a.value
    assert value is not None  # _check_literal refused what reads as no value
    if not kind or a.kind == kind:
        return value
    if kind == "double" and a.kind == "int":
        return float(value)
    raise RunError(
        f"--run {call.written}: {what}: {a.text} is not {_article(kind)}: write {_WRITE[kind]}"
    )


def _check_literal(call: RunCall, a: Literal, name: str, uml: str, number: int) -> None:
    """Refuse what reads as no value at all, whatever the parameter."""
    what = (
        f"argument {number} of {call.operation}, parameter {name} ({uml or 'no type'})"
        if name
        else f"argument {a.text}"
    )
    if a.kind == "long number":
        raise RunError(
            f"--run {call.written}: {what}: a number of more than {MAX_NUMBER} characters: "
            f"write one of at most {MAX_NUMBER}"
        )
    if a.kind == "not finite":
        raise RunError(
            f"--run {call.written}: {what}: {a.text} is not a finite number: write a finite "
            "number (2.5, -1e3)"
        )
    if a.kind == "int" and len(a.text) >= 20:
        raise RunError(
            f"--run {call.written}: {what}: {a.text} has more than 19 characters, more than "
            "an int of the descriptor holds: write a smaller whole number"
        )
    if isinstance(a.value, float) and not math.isfinite(a.value):
        raise RunError(
            f"--run {call.written}: {what}: {a.text} is beyond a double's range: write a "
            "finite number"
        )
    if not a.kind:
        raise RunError(
            f"--run {call.written}: {what}: {a.text!r} is not a value: write a number, true or "
            "false, or a string in quotes (nothing is evaluated)"
        )


def _kind(uml: str) -> str | None:
    """A parameter's value kind: ``int``, ``double``, ``bool``, ``string``; empty for a parameter
    without a type; None for a type no command line can give (a class of the model)."""
    text = uml.strip()
    if not text or text == "?":
        return ""
    kind = value_kind(text)
    if kind != "string" or text.lower() in ("string", "str", "char", "text"):
        return kind
    return None


def _article(kind: str) -> str:
    return {"int": "an int", "double": "a double", "bool": "a bool", "string": "a string"}[kind]


def _example(uml: str) -> str:
    return {"int": "5", "double": "2.5", "bool": "true", "string": "'text'"}.get(
        _kind(uml) or "", "..."
    )


def _count(n: int) -> str:
    return "no argument" if n == 0 else f"{n} argument{'s' if n != 1 else ''}"


def _signature(name: str, params: Sequence) -> str:
    inside = ", ".join(f"{p.name}: {p.type}" if p.type else p.name for p in params)
    return f"{name}({inside})"


def _cut(text: str, limit: int = 60) -> str:
    """``text`` cut to ``limit`` characters (a hostile one is not echoed whole)."""
    return text if len(text) <= limit else text[:limit] + "..."


def _short(text: str, limit: int = 60) -> str:
    """``text`` quoted, cut to ``limit`` characters."""
    return repr(_cut(text, limit))


__all__ = ["RunCall", "RunError", "bind_run", "parse_run"]
