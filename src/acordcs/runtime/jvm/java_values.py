"""Values crossing between Python and a hosted Java component.

Into Java, JPype converts what a method's parameter types take (a Python ``float`` to a
``double``, an ``int`` to an ``int`` or ``long``, a ``str`` to a ``String``; as an ``Object``,
``Double``, ``Long``, ``String``, ``Boolean``); lists, tuples and dicts become a
``java.util.ArrayList`` and ``HashMap`` of converted values. Out of Java, :func:`to_python`
makes plain Python values of what a method returns or a port call passes: boxed numbers and
booleans, strings, arrays and ``java.util`` lists and maps; any other Java object is passed as
it is (a JPype proxy of it).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

PLAIN = frozenset((type(None), bool, int, float, str))
"""The Python types of values that need no conversion either way."""

_CONVERTERS: dict[type, Callable[[Any], Any]] = {}
"""The conversion out of Java of each type met (its Python type fixes which one applies)."""


def to_python(value: Any) -> Any:
    """A plain Python value for ``value``, which came out of Java (see the module's docstring)."""
    kind = type(value)
    if kind in PLAIN:
        return value
    convert = _CONVERTERS.get(kind)
    if convert is None:
        convert = _CONVERTERS[kind] = _converter(value)
    return convert(value)


def _same(value: Any) -> Any:
    return value


def _sequence(value: Any) -> list[Any]:
    return [to_python(v) for v in value]


def _table(value: Any) -> dict[Any, Any]:
    return {to_python(k): to_python(v) for k, v in value.entrySet()}


def _converter(value: Any) -> Callable[[Any], Any]:
    """How to convert values of ``value``'s type."""
    import jpype

    if isinstance(value, bool | jpype.JBoolean):
        return bool
    if isinstance(value, jpype.JString | jpype.JChar):
        return str
    if isinstance(value, int):  # JInt, JLong, java.lang.Integer, ... subclass int
        return int
    if isinstance(value, float):
        return float
    if isinstance(value, jpype.JArray):
        return _sequence
    if isinstance(value, jpype.JObject):
        if isinstance(value, jpype.JClass("java.lang.Boolean")):
            return lambda v: bool(v.booleanValue())
        if isinstance(value, jpype.JClass("java.util.Map")):
            return _table
        if isinstance(value, jpype.JClass("java.util.Collection")):
            return _sequence
    return _same


def to_java(value: Any) -> Any:
    """``value``, made something JPype passes as a Java ``Object`` (see the module's docstring)."""
    if type(value) in PLAIN:
        return value
    import jpype

    if isinstance(value, list | tuple):
        out = jpype.JClass("java.util.ArrayList")()
        for v in value:
            out.add(to_java(v))
        return out
    if isinstance(value, dict):
        table = jpype.JClass("java.util.HashMap")()
        for k, v in value.items():
            table.put(to_java(k), to_java(v))
        return table
    return value
