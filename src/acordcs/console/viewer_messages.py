"""What a viewer sends a console, read strictly: a JSON object of at most :data:`MAX_MESSAGE`
bytes naming a known command with arguments of the right type and range. Anything else is refused
with a message saying what was wrong and what is accepted; nothing a viewer sends reaches what the
console drives unchecked. Numbers are checked by type and range before any float operation (a
huge integer is out of range, ``NaN``, ``Infinity`` and ``1e309`` are not finite), and a refusal
shows what was sent in at most 40 characters.

Each console has its own commands (the WebLab's ``drive``, the generic console's ``call``); what
they share is here: :func:`read_object` (the size, text, JSON object checks), :func:`number`,
:func:`shown`, :func:`valid_token` and the two commands every console answers, ``ping`` and
``auth`` (:func:`common_command`).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any

MAX_MESSAGE = 4096
"""Bytes of one viewer message; a longer one is refused unread."""


class CommandError(ValueError):
    """A viewer message that is not a valid command; ``str()`` says why and what is accepted."""


@dataclass(frozen=True)
class Command:
    """A command read: its ``name`` and ``args`` (the session's method and its keyword
    arguments); ``echo``: what the answer repeats (the generic console's ``ref``, which pairs an
    answer with its request)."""

    name: str
    args: dict[str, Any] = field(default_factory=dict)
    echo: dict[str, Any] = field(default_factory=dict)


def number(message: dict, key: str, lo: float, hi: float) -> float:
    """``message[key]`` as a float from ``lo`` to ``hi``. The range is checked on the value as
    JSON gave it, before any float operation: an integer of 401 digits is out of range, not an
    ``OverflowError`` (``float()`` and ``math.isfinite`` of it raise one)."""
    value = message.get(key)
    said = shown(value)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise CommandError(f"{key!r} must be a number from {lo:g} to {hi:g}, not {said}")
    if isinstance(value, float) and not math.isfinite(value):  # NaN, Infinity, 1e309
        raise CommandError(f"{key!r} must be a number from {lo:g} to {hi:g}, not {said}")
    if not lo <= value <= hi:  # exact for integers of any size: no conversion to float
        raise CommandError(f"{key!r} must be from {lo:g} to {hi:g}, not {said}")
    return float(value)


def shown(value: Any) -> str:
    """``value`` in a refusal, at most 40 characters or so: a huge integer by its number of
    digits (never converted to float), a nested value as such."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 64:
        try:  # json.loads reads at most sys.get_int_max_str_digits() digits: so can str()
            digits = len(str(abs(value)))
        except ValueError:
            digits = int(math.log10(abs(value))) + 1
        return f"an integer of {digits} digits"
    try:
        return f"{value!r:.40}"
    except RecursionError:  # nested about as deep as json.loads goes
        return f"a deeply nested {type(value).__name__}"


def valid_token(token: Any) -> bool:
    """Whether ``token`` may be a session's token: 1 to 128 printable ASCII characters (the
    consoles' are URL-safe base64); anything else is refused before the access service reads
    it."""
    return (
        isinstance(token, str)
        and 1 <= len(token) <= 128
        and token.isascii()
        and token.isprintable()
    )


def read_object(text: str | bytes) -> dict[str, Any]:
    """The JSON object ``text`` holds, or :class:`CommandError`: at most :data:`MAX_MESSAGE`
    bytes, text (not binary), JSON, an object."""
    size = len(text.encode("utf-8") if isinstance(text, str) else text)
    if size > MAX_MESSAGE:
        raise CommandError(f"message of {size} bytes refused: at most {MAX_MESSAGE}")
    if isinstance(text, bytes):
        raise CommandError("binary messages are refused: send a JSON object as text")
    try:
        message = json.loads(text)
    except (ValueError, RecursionError):
        raise CommandError('not JSON: send an object such as {"cmd": "ping"}') from None
    if not isinstance(message, dict):
        raise CommandError('not a JSON object: send an object such as {"cmd": "ping"}')
    return message


def common_command(message: dict[str, Any]) -> Command | None:
    """``ping`` or ``auth`` (its token checked by :func:`valid_token`), or None for another
    command."""
    name = message.get("cmd")
    if name == "ping":
        return Command(name)
    if name == "auth":
        token = message.get("token")
        if not valid_token(token):
            raise CommandError("'token' must be a string of 1 to 128 printable ASCII characters")
        return Command(name, {"token": token})
    return None
