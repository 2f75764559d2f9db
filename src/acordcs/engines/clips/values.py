"""Values of model variables: which Python values the CLIPS engine takes (how they come back from
CLIPS: :func:`.records.read_value`).

A value is a bool, a number (int within 64 bits, or float, NaN and infinities included), a string
(no NUL character: CLIPS strings are C strings) or None (never set). Declared types narrow that:
a ``number`` variable takes numbers only, and so on.
"""

from __future__ import annotations

import numbers

Value = bool | int | float | str | None

KINDS = ("number", "string", "boolean")

_KIND_OF_TYPE = {
    **dict.fromkeys(
        [
            "int",
            "integer",
            "long",
            "short",
            "byte",
            "double",
            "float",
            "real",
            "number",
            "natural",
            "unlimitednatural",
            "eint",
            "einteger",
            "elong",
            "eshort",
            "edouble",
            "efloat",
            "ebigdecimal",
            "ebiginteger",
        ],
        "number",
    ),
    **dict.fromkeys(["string", "str", "char", "text", "estring"], "string"),
    **dict.fromkeys(["bool", "boolean", "eboolean"], "boolean"),
}

_INT_MIN, _INT_MAX = -(2**63), 2**63 - 1


def kind_of_type(type_name: str | None) -> str | None:
    """The value kind of a model type name (UML/Ecore/Python spelling), or None when it is unknown."""
    if not type_name:
        return None
    if type_name in KINDS:
        return type_name
    return _KIND_OF_TYPE.get(type_name.strip().lower())


def kind_of(value: Value) -> str:
    if value is None:
        return "unset"
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, str):
        return "string"
    return "number"


def shown(value: object, limit: int = 60) -> str:
    """``repr(value)`` for a message, cut to about ``limit`` characters; an integer too long to
    print (past 4,300 digits Python refuses) is described by its size."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 200:
        digits = int(value.bit_length() * 0.30103) + 1
        return f"{'-' if value < 0 else ''}<an integer of about {digits} digits>"
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def normalise(value: object, kind: str | None) -> Value:
    """``value`` as one of the exact types CLIPS receives. Raises ValueError saying what is wrong."""
    exact = type(value)
    if exact is float and kind in (None, "number"):  # the hot path: a monitor pushing a reading
        return value  # type: ignore[return-value]
    if isinstance(value, bool):
        out: Value = value
    elif isinstance(value, numbers.Integral):
        out = int(value)
        if not _INT_MIN <= out <= _INT_MAX:
            raise ValueError(
                f"the integer {shown(out)} does not fit in 64 bits; pass it as a float"
            )
    elif isinstance(value, numbers.Real):
        out = float(value)
    elif isinstance(value, str):
        out = str(value)
        if "\x00" in out:
            raise ValueError(
                "the string contains a NUL character, which CLIPS cannot hold; remove it"
            )
        try:
            out.encode("utf-8")
        except UnicodeEncodeError:
            raise ValueError(
                "the string is not valid Unicode (lone surrogate); fix its encoding"
            ) from None
    elif value is None:
        return None
    else:
        raise ValueError(
            f"a {type(value).__name__} is not a rule value; pass a bool, a number or a string"
        )
    if kind is not None and kind_of(out) != kind:
        raise ValueError(
            f"the variable is declared {kind}, and {shown(out)} is {kind_of(out)}; pass a {kind}"
        )
    return out


def parse_default(text: str, kind: str | None) -> Value:
    """A model's default value (always text in the model) as a value of ``kind``."""
    raw = text.strip()
    if kind == "string":
        if len(raw) >= 2 and raw[0] == raw[-1] and raw[0] in "'\"":
            return raw[1:-1]
        return text
    if raw.lower() in ("true", "false") and kind in (None, "boolean"):
        return raw.lower() == "true"
    if kind in (None, "number"):
        try:
            return int(raw)
        except ValueError:
            pass
        try:
            number = float(raw)
        except ValueError:
            if kind is None:
                return text
            raise ValueError(f"{shown(text)} is not a number") from None
        return number
    raise ValueError(f"{shown(text)} is not true or false")
