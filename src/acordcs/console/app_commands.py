"""What a viewer may send the console of an application (:mod:`.live_session`), read strictly
(:mod:`.viewer_messages`: at most 4 KB, a JSON object, numbers range-checked before any
arithmetic). Every command may carry ``"ref"``, an integer from 0 to 2**31 - 1 the answer repeats.

- ``{"cmd": "ping"}``, ``{"cmd": "auth", "token": "..."}``: as every console's;
- ``{"cmd": "call", "component": "Fan", "port": "FanPort", "operation": "setSpeed", "args":
  [40]}``: an operation of a provided synchronous port of the model, each argument of its
  parameter's type (``int``: an integer of at most 64 bits; ``double``: a finite number;
  ``bool``; ``string``: at most 1000 characters), as many as it has ``in`` parameters (token);
- ``{"cmd": "set", "element": "Vent", "attribute": "opening", "value": 40}``: a property of a
  component of the model, its value of the property's type (token);
- ``{"cmd": "plan"}``: the plan of an update from the console's model file (token);
- ``{"cmd": "apply", "plan": "<sha256 of the plan shown>"}``: apply that plan (token).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from typing import Any

from acordcs.console.viewer_messages import (
    Command,
    CommandError,
    common_command,
    read_object,
    shown,
)
from acordcs.typed_values import value_kind

MAX_TEXT = 1000
"""Characters of a string argument."""

_DIGEST = re.compile(r"[0-9a-f]{64}\Z")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,199}\Z")


def _argument(value: Any, type_name: str, name: str) -> Any:
    """``value`` as parameter ``name`` of UML type ``type_name`` takes it, or CommandError."""
    kind = value_kind(type_name)
    if kind == "bool":
        if not isinstance(value, bool):
            raise CommandError(f"{name!r} is a bool: true or false, not {shown(value)}")
        return value
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int) or not -(2**63) <= value < 2**63:
            raise CommandError(f"{name!r} is an integer of at most 64 bits, not {shown(value)}")
        return value
    if kind == "double":
        finite = isinstance(value, int | float) and not isinstance(value, bool)
        if isinstance(value, int) and finite and not -(2**1023) < value < 2**1023:
            finite = False  # an integer float() cannot hold: checked before converting
        if not finite or (isinstance(value, float) and not math.isfinite(value)):
            raise CommandError(f"{name!r} is a finite number, not {shown(value)}")
        return float(value)
    if not isinstance(value, str) or len(value) > MAX_TEXT:
        raise CommandError(
            f"{name!r} is a text of at most {MAX_TEXT} characters, not {shown(value)}"
        )
    return value


def parse(
    text: str | bytes,
    operations: Iterable[Mapping[str, Any]],
    properties: Iterable[Mapping[str, Any]] = (),
) -> Command:
    """The command in ``text`` (``operations``, ``properties``: the page model's, what ``call``
    and ``set`` may name), or :class:`CommandError`."""
    message = read_object(text)
    ref = message.get("ref")
    echo: dict[str, Any] = {}
    if ref is not None:
        if isinstance(ref, bool) or not isinstance(ref, int) or not 0 <= ref < 2**31:
            raise CommandError(f"'ref' must be an integer from 0 to 2147483647, not {shown(ref)}")
        echo = {"ref": ref}
    common = common_command(message)
    if common is not None:
        return Command(common.name, common.args, echo)
    name = message.get("cmd")
    if name == "plan":
        return Command(name, {}, echo)
    if name == "apply":
        plan = message.get("plan")
        if not isinstance(plan, str) or not _DIGEST.match(plan):
            raise CommandError(
                f"'plan' must be the plan's sha256 (64 hex digits), not {shown(plan)}"
            )
        return Command(name, {"plan": plan}, echo)
    if name == "set":
        element, attribute = message.get("element"), message.get("attribute")
        found = next(
            (p for p in properties if p["element"] == element and p["attribute"] == attribute),
            None,
        )
        if found is None:
            raise CommandError(
                f"{shown(element)}.{shown(attribute)} is not a property of a component of the model"
            )
        value = _argument(message.get("value"), found["type"], str(attribute))
        return Command(name, {"element": element, "attribute": attribute, "value": value}, echo)
    if name == "call":
        names = [message.get(k) for k in ("component", "port", "operation")]
        if not all(isinstance(n, str) and _NAME.match(n) for n in names):
            raise CommandError("'component', 'port' and 'operation' must be the model's names")
        found = next(
            (o for o in operations
             if [o["component"], o["port"], o["name"]] == names),
            None,
        )  # fmt: skip
        if found is None:
            raise CommandError(
                f"{'.'.join(names)} is not an operation of a provided synchronous port of the model"
            )
        args = message.get("args", [])
        wanted = [p for p in found["parameters"] if p["direction"] in ("in", "inout")]
        if not isinstance(args, list) or len(args) != len(wanted):
            raise CommandError(
                f"'args' must be a list of {len(wanted)} value(s): "
                f"{', '.join(p['name'] + ': ' + p['type'] for p in wanted) or 'none'}"
            )
        typed = [_argument(a, p["type"], p["name"]) for a, p in zip(args, wanted, strict=True)]
        component, port, operation = names
        return Command(name, {"component": component, "port": port, "operation": operation,
                              "args": typed}, echo)  # fmt: skip
    raise CommandError(
        f"unknown command {shown(name)}: the commands are auth, call, set, plan, apply, ping"
    )
