"""What rules do in Python: call operations of model elements, and report what went wrong.

Operations are declared (from the model, or by hand) and bound (to a callable, or to an object whose
methods they are). Calls and faults come back from CLIPS as records (see :mod:`.prelude`); they are
dealt with here, after the CLIPS run, so a raising operation never disturbs CLIPS.
"""

from __future__ import annotations

import logging
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

from acordcs.engines.clips.values import Value
from acordcs.rules import Name

log = logging.getLogger("acordcs.engines.clips")


@dataclass(frozen=True, slots=True)
class FireError:
    """Something that went wrong while firing: where, and what."""

    ruleset: str
    rule: str | None
    message: str

    def __str__(self) -> str:
        where = f"rule set {self.ruleset!r}" + (f", rule {self.rule!r}" if self.rule else "")
        return f"{where}: {self.message}"


class Faults:
    """Counts every fault, keeps the last 100, logs each distinct one once (then at DEBUG)."""

    def __init__(self) -> None:
        self.count = 0
        self.recent: deque[FireError] = deque(maxlen=100)
        self._logged: set[tuple[str, str | None, str]] = set()

    def add(
        self, ruleset: str, rule: str | None, message: str, exc: BaseException | None = None
    ) -> None:
        self.count += 1
        error = FireError(ruleset, rule, message)
        self.recent.append(error)
        key = (ruleset, rule, message[:120])
        if key in self._logged:
            log.debug("%s", error)
            return
        if len(self._logged) > 1000:  # an endless variety of messages must not grow memory
            self._logged.clear()
        self._logged.add(key)
        log.warning("%s (counted; the fire went on)", error)
        if exc is not None:
            log.debug("traceback of the operation", exc_info=exc)


class OperationTable:
    """Declared and bound operations, and the numbers CLIPS records use for them."""

    def __init__(self) -> None:
        self.declared: dict[str, tuple[str, ...] | None] = {}
        self._index: dict[str, int] = {}
        self._names: list[str] = [""]
        self._functions: dict[str, Callable[..., object]] = {}
        self._objects: dict[str, object] = {}
        self.aliases: dict[str, str] = {}  # names as rules write them -> declared names

    def declare(self, name: str, parameters: tuple[str, ...] | None) -> None:
        self.declared[name] = parameters

    def bind(self, element: str, obj: object) -> None:
        self._objects[element] = obj

    def names(self) -> list[str]:
        """Operation names by the number CLIPS records use (index 0 unused)."""
        return list(self._names)

    def bind_function(self, name: str, function: Callable[..., object]) -> None:
        self._functions[name] = function

    def number_for(self, name: Name, nargs: int) -> int:
        """The number of the operation a rule calls. LookupError when declarations rule it out."""
        full = self.aliases.get(name.text, name.text)
        if self.declared:
            if full not in self.declared and "." not in full:
                matches = [n for n in self.declared if n.rpartition(".")[2] == full]
                full = matches[0] if len(matches) == 1 else full
            if full not in self.declared:
                known = ", ".join(sorted(self.declared))
                raise LookupError(
                    f"unknown operation {name.text!r} (declared: {known}); declare it or fix the name"
                )
            parameters = self.declared[full]
            if parameters is not None and len(parameters) != nargs:
                raise LookupError(
                    f"operation {full} takes {len(parameters)} argument(s) ({', '.join(parameters)}), not {nargs}"
                )
        number = self._index.get(full)
        if number is None:
            number = self._index[full] = len(self._names)
            self._names.append(full)
        return number

    def function(self, name: str) -> Callable[..., object] | None:
        found = self._functions.get(name)
        if found is not None:
            return found
        element, dot, member = name.rpartition(".")
        if dot:
            attr = getattr(self._objects.get(element), member, None)
            return attr if callable(attr) else None
        candidates = [f for n, f in self._functions.items() if n.rpartition(".")[2] == name]
        candidates += [a for o in self._objects.values() if callable(a := getattr(o, name, None))]
        return candidates[0] if len(candidates) == 1 else None

    def invoke(
        self, op: int | str, args: list[Value], ruleset: str, rule: str | None, faults: Faults
    ) -> None:
        """Call operation ``op`` (number, or name) with ``args`` (rule values already)."""
        name = self._names[op] if type(op) is int else op
        function = self._functions.get(name) or self.function(name)
        if function is None:
            element = name.rpartition(".")[0] or "Element"
            faults.add(
                ruleset,
                rule,
                f"operation {name!r} is not bound; call engine.bind_operation({name!r}, function)"
                f" or engine.bind({element!r}, obj)",
            )
            return
        try:
            function(*args)
        except Exception as err:  # an application callback must not stop the other rules' actions
            faults.add(
                ruleset, rule, f"operation {name!r} raised {type(err).__name__}: {err}", exc=err
            )
