"""What a viewer may send, read strictly: a JSON object of at most :data:`MAX_MESSAGE` bytes naming a
known command with arguments of the right type and range. Anything else is refused with a message
saying what was wrong and what is accepted; nothing a viewer sends reaches the experiment
unchecked. Numbers are checked by type and range before any float operation (a huge integer is
out of range, ``NaN``, ``Infinity`` and ``1e309`` are not finite), and a refusal shows what was
sent in at most 40 characters.

Commands:

- ``{"cmd": "auth", "token": "..."}``: present the session's token (the access service decides);
- ``{"cmd": "start", "profile": "residential", "seed": 3}``: start an experiment (token needed);
- ``{"cmd": "stop"}``: stop it (token needed);
- ``{"cmd": "drive", "speed": 80, "turn": -10}``: take manual control: mm/s, and the bearing in degrees (+ left) to head for (token);
- ``{"cmd": "release"}``: hand control back to the Navigator (token needed);
- ``{"cmd": "ping"}``: answered with ``pong`` (no token).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any

MAX_MESSAGE = 4096
"""Bytes of one viewer message; a longer one is refused unread."""

MAX_SPEED = 500.0
"""mm/s, the largest manual speed accepted (the robot's own cap applies after)."""

MAX_TURN = 180.0
"""degrees either way: the bearing of the point the robot heads for."""

CONTROL = frozenset({"start", "stop", "drive", "release"})
"""Commands that change the experiment: refused without the session's token."""


class CommandError(ValueError):
    """A viewer message that is not a valid command; ``str()`` says why and what is accepted."""


@dataclass(frozen=True)
class Command:
    name: str
    args: dict[str, Any] = field(default_factory=dict)

    @property
    def controls(self) -> bool:
        return self.name in CONTROL


def _number(message: dict, key: str, lo: float, hi: float) -> float:
    """``message[key]`` as a float from ``lo`` to ``hi``. The range is checked on the value as
    JSON gave it, before any float operation: an integer of 401 digits is out of range, not an
    ``OverflowError`` (``float()`` and ``math.isfinite`` of it raise one)."""
    value = message.get(key)
    shown = _shown(value)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise CommandError(f"{key!r} must be a number from {lo:g} to {hi:g}, not {shown}")
    if isinstance(value, float) and not math.isfinite(value):  # NaN, Infinity, 1e309
        raise CommandError(f"{key!r} must be a number from {lo:g} to {hi:g}, not {shown}")
    if not lo <= value <= hi:  # exact for integers of any size: no conversion to float
        raise CommandError(f"{key!r} must be from {lo:g} to {hi:g}, not {shown}")
    return float(value)


def _shown(value: Any) -> str:
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
    console's are URL-safe base64); anything else is refused before the access service reads
    it."""
    return (
        isinstance(token, str)
        and 1 <= len(token) <= 128
        and token.isascii()
        and token.isprintable()
    )


def parse(text: str | bytes, profiles: tuple[str, ...]) -> Command:
    """The command in ``text``, or :class:`CommandError`."""
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
    name = message.get("cmd")
    if name == "ping" or name == "stop" or name == "release":
        return Command(name)
    if name == "auth":
        token = message.get("token")
        if not valid_token(token):
            raise CommandError("'token' must be a string of 1 to 128 printable ASCII characters")
        return Command(name, {"token": token})
    if name == "start":
        profile = message.get("profile")
        if profile not in profiles:
            raise CommandError(
                f"'profile' must be one of {', '.join(profiles)}, not {_shown(profile)}"
            )
        seed = message.get("seed", 0)
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**31:
            raise CommandError(
                f"'seed' must be an integer from 0 to 2147483647, not {_shown(seed)}"
            )
        return Command(name, {"profile": profile, "seed": seed})
    if name == "drive":
        speed = _number(message, "speed", 0.0, MAX_SPEED)
        turn = _number(message, "turn", -MAX_TURN, MAX_TURN)
        return Command(name, {"speed": speed, "turn": turn})
    known = "auth, start, stop, drive, release, ping"
    raise CommandError(f"unknown command {_shown(name)}: the commands are {known}")
