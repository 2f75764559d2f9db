"""What a viewer may send, read strictly: a JSON object of at most :data:`MAX_MESSAGE` bytes naming a
known command with arguments of the right type and range. Anything else is refused with a message
saying what was wrong and what is accepted; nothing a viewer sends reaches the experiment
unchecked.

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
    value = message.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise CommandError(f"{key!r} must be a number from {lo:g} to {hi:g}, not {value!r:.40}")
    if not lo <= value <= hi:
        raise CommandError(f"{key!r} must be from {lo:g} to {hi:g}, not {value:g}")
    return float(value)


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
        if not isinstance(token, str) or not 1 <= len(token) <= 128:
            raise CommandError("'token' must be a string of 1 to 128 characters")
        return Command(name, {"token": token})
    if name == "start":
        profile = message.get("profile")
        if profile not in profiles:
            raise CommandError(
                f"'profile' must be one of {', '.join(profiles)}, not {profile!r:.40}"
            )
        seed = message.get("seed", 0)
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**31:
            raise CommandError(f"'seed' must be an integer from 0 to 2147483647, not {seed!r:.40}")
        return Command(name, {"profile": profile, "seed": seed})
    if name == "drive":
        speed = _number(message, "speed", 0.0, MAX_SPEED)
        turn = _number(message, "turn", -MAX_TURN, MAX_TURN)
        return Command(name, {"speed": speed, "turn": turn})
    known = "auth, start, stop, drive, release, ping"
    raise CommandError(f"unknown command {name!r:.40}: the commands are {known}")
