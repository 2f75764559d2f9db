"""How a model's values are typed, for the descriptor and the model checks alike: numbers as the
XSD lexical forms EMF and Java read, a UML type read as one of the descriptor's value kinds, and
a default read by its kind. A leaf module: checking a model does not load the descriptor package.
"""

from __future__ import annotations

import math
import re

Value = bool | int | float | str
"""A typed default: ``int`` for kind ``int``, ``float`` for ``double``, ``bool``, ``str``."""

# xsd:double and xsd:int lexical forms (ASCII digits only), as EMF and Java read tag values.
_REAL = re.compile(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?")
_INTEGER = re.compile(r"[+-]?[0-9]+")
_INT_TYPES = frozenset({"int", "integer", "long", "short"})
_REAL_TYPES = frozenset({"double", "float", "real", "number"})
_BOOL_TYPES = frozenset({"bool", "boolean"})
_TRUE = frozenset({"true", "1", "yes"})


def parse_real(text: str) -> float | None:
    """A model's or descriptor's number as a finite xsd:double, or None."""
    text = text.strip()
    if not _REAL.fullmatch(text):
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def parse_integer(text: str) -> int | None:
    """A model's number as an xsd:int-like integer (under 20 characters), or None."""
    text = text.strip()
    return int(text) if _INTEGER.fullmatch(text) and len(text) < 20 else None


def parse_boolean(text: str) -> bool | None:
    """A Boolean tag's value (``true`` or ``false``, any case, as EMF reads it), or None."""
    return {"true": True, "false": False}.get(text.strip().lower())


def value_kind(type_name: str | None, *, variable: bool = False) -> str:
    """How a UML type is read: ``int``, ``double``, ``bool`` or ``string``. A linguistic variable
    of any type but an integer one is a ``double``."""
    kind = (type_name or "").strip().lower()
    if kind in _INT_TYPES:
        return "int"
    if kind in _REAL_TYPES or variable:
        return "double"
    if kind in _BOOL_TYPES:
        return "bool"
    return "string"


def typed_default(kind: str, text: str | None, range_min: float | None = None) -> Value:
    """A UML default value read by its kind (see :func:`value_kind`); these are the initial values
    :func:`acordcs.runtime.assembly.assemble` gives properties.

    Unset (None or empty): a linguistic variable gets the minimum of its range (``range_min``),
    anything else 0, 0.0, False or "". An ``int`` default may be written as a real (``10.0``: 10,
    truncated as the runtime does); numbers must be finite xsd:double literals. A ``bool`` is true
    for ``true``, ``1`` or ``yes`` (any case), false otherwise. Raises ValueError for a number that
    does not parse.
    """
    unset = text is None or text.strip() == ""
    if kind in ("int", "double"):
        if unset:
            number = range_min if range_min is not None else 0.0
        else:
            number = parse_real(text)  # type: ignore[arg-type]
            if number is None:
                raise ValueError(text)
        return int(number) if kind == "int" else float(number)
    if kind == "bool":
        return (text or "").strip().lower() in _TRUE
    return text if text is not None else ""
