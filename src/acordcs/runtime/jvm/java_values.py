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

from typing import Any


def to_python(value: Any) -> Any:
    """A plain Python value for ``value``, which came out of Java (see the module's docstring)."""
    import jpype

    if value is None or type(value) in (bool, int, float, str):
        return value
    if isinstance(value, bool | jpype.JBoolean):
        return bool(value)
    if isinstance(value, jpype.JString):
        return str(value)
    if isinstance(value, int):  # JInt, JLong, java.lang.Integer, ... subclass int
        return int(value)
    if isinstance(value, float):
        return float(value)
    if isinstance(value, jpype.JChar):
        return str(value)
    if isinstance(value, jpype.JArray):
        return [to_python(v) for v in value]
    if isinstance(value, jpype.JObject):
        if isinstance(value, jpype.JClass("java.lang.Boolean")):
            return bool(value.booleanValue())
        if isinstance(value, jpype.JClass("java.util.Map")):
            return {to_python(k): to_python(v) for k, v in value.entrySet()}
        if isinstance(value, jpype.JClass("java.util.Collection")):
            return [to_python(v) for v in value]
    return value


def to_java(value: Any) -> Any:
    """``value``, made something JPype passes as a Java ``Object`` (see the module's docstring)."""
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
