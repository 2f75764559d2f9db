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

from acordcs.console.viewer_messages import (
    MAX_MESSAGE,
    Command,
    CommandError,
    common_command,
    number,
    read_object,
    shown,
)

__all__ = ["MAX_MESSAGE", "Command", "CommandError", "parse"]

MAX_SPEED = 500.0
"""mm/s, the largest manual speed accepted (the robot's own cap applies after)."""

MAX_TURN = 180.0
"""degrees either way: the bearing of the point the robot heads for."""


def parse(text: str | bytes, profiles: tuple[str, ...]) -> Command:
    """The command in ``text``, or :class:`CommandError`."""
    message = read_object(text)
    common = common_command(message)
    if common is not None:
        return common
    name = message.get("cmd")
    if name == "stop" or name == "release":
        return Command(name)
    if name == "start":
        profile = message.get("profile")
        if profile not in profiles:
            raise CommandError(
                f"'profile' must be one of {', '.join(profiles)}, not {shown(profile)}"
            )
        seed = message.get("seed", 0)
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**31:
            raise CommandError(f"'seed' must be an integer from 0 to 2147483647, not {shown(seed)}")
        return Command(name, {"profile": profile, "seed": seed})
    if name == "drive":
        speed = number(message, "speed", 0.0, MAX_SPEED)
        turn = number(message, "turn", -MAX_TURN, MAX_TURN)
        return Command(name, {"speed": speed, "turn": turn})
    known = "auth, start, stop, drive, release, ping"
    raise CommandError(f"unknown command {shown(name)}: the commands are {known}")
