"""One way to register, for targets, engines and checks alike (as textX registers its generators):
an explicit table of the built-in ones, by ``"module:attribute"`` name, loaded with importlib when
first asked for, plus the entry points of a group for other packages' plug-ins. Nothing registers
itself as a side effect of being imported.

:class:`PluginTable` does the loading; each registry says what its group is, what its built-in
table holds and what an entry point's object must be (``accept``):

- targets: :data:`acordcs.generator.target.ENTRY_POINT_GROUP` (``acordcs.targets``);
- engines: :data:`acordcs.engines.engine_registry.ENTRY_POINT_GROUP` (``acordcs.engines``);
- checks: :data:`acordcs.model.checks.ENTRY_POINT_GROUP` (``acordcs.checks``).

A plug-in that fails to load never stops the others: what went wrong is in
:attr:`PluginTable.problems`, for the CLI to print as warnings.
"""

from __future__ import annotations

import importlib
import os
import sys
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

T = TypeVar("T")


class Refused(Exception):
    """Raised by a table's ``accept`` for an entry point's object that is not what the group
    takes; its message says what it is and what it should be."""


def load_attribute(reference: str) -> Any:
    """The object ``"package.module:attribute"`` names (the attribute may be dotted)."""
    module_name, _, attribute = reference.partition(":")
    found: Any = importlib.import_module(module_name)
    for part in attribute.split(".") if attribute else ():
        found = getattr(found, part)
    return found


def declared_somewhere(group: str) -> bool:
    """Whether some distribution on sys.path may declare entry points of ``group``: a look at the
    ``entry_points.txt`` files of the ``*.dist-info`` and ``*.egg-info`` directories, which spares
    every command that has no plug-in the 15 ms importlib.metadata takes to import. True (ask
    importlib.metadata) whenever a path entry is not a plain directory (a zip, an egg)."""
    header = f"[{group}]".encode()
    for entry in sys.path:
        try:
            names = os.listdir(entry or ".")
        except NotADirectoryError:
            return True
        except OSError:
            continue
        for name in names:
            if name.endswith(".egg"):
                return True
            if name.endswith((".dist-info", ".egg-info")):
                try:
                    with open(os.path.join(entry or ".", name, "entry_points.txt"), "rb") as f:
                        if header in f.read().replace(b" ", b""):
                            return True
                except OSError:
                    continue
    return False


def installed_entry_points(group: str) -> list[Any]:
    """The entry points of ``group`` the installed distributions declare (importlib.metadata)."""
    if not declared_somewhere(group):
        return []
    from importlib import metadata

    return list(metadata.entry_points(group=group))


@dataclass
class PluginTable(Generic[T]):
    """The plug-ins of one kind: ``builtin`` (name -> ``"module:attribute"``, acordcs's own) and the
    entry points of ``group``, loaded once, on the first :meth:`load`.

    ``accept(name, loaded, origin)`` turns what a reference or an entry point names into the
    table's item, or raises :class:`Refused`; ``name_of`` and ``origin_of`` read an item's own name
    and origin (an item is listed under its own name); ``noun`` names the kind in messages.
    ``entry_points`` lists the group's entry points (default: the installed distributions'; a
    test gives its own). ``extra`` items join the table as they are (a script's or a test's own)."""

    group: str
    noun: str
    builtin: Mapping[str, str]
    accept: Callable[[str, Any, str], T]
    name_of: Callable[[str, T], str] = lambda name, item: name
    origin_of: Callable[[T], str] = lambda item: "?"
    entry_points: Callable[[str], Iterable[Any]] = installed_entry_points
    extra: Mapping[str, T] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    _loaded: dict[str, T] | None = field(default=None, init=False, repr=False)

    def load(self) -> dict[str, T]:
        """Every item by name, sorted: the built-in ones, then the plug-ins whose names are free."""
        if self._loaded is None:
            found = {
                name: self.accept(name, load_attribute(ref), "acordcs")
                for name, ref in self.builtin.items()
            }
            found.update(self.extra)
            for point in self.entry_points(self.group):
                self._add_point(found, point)
            self._loaded = dict(sorted(found.items()))
        return dict(self._loaded)

    def _add_point(self, found: dict[str, T], point: Any) -> None:
        dist = getattr(getattr(point, "dist", None), "name", None) or "an installed package"
        where = f"entry point {point.name} = {point.value} (from {dist}, group {self.group})"
        try:
            loaded = point.load()
        except Exception as err:  # a broken plug-in must not stop the others
            self.problems.append(
                f"{where} could not be loaded: {type(err).__name__}: {err}; "
                "fix or uninstall that package"
            )
            return
        try:
            item = self.accept(point.name, loaded, dist)
        except Refused as err:
            self.problems.append(f"{where} {err}")
            return
        name = self.name_of(point.name, item)
        if name != point.name:
            self.problems.append(
                f"{where} is {self.noun} {name!r}: registered as {name!r}; "
                f"give the entry point the {self.noun}'s name"
            )
        existing = found.get(name)
        if existing is not None and existing is not item:
            self.problems.append(
                f"{where}: {self.noun} {name!r} already exists ({self.origin_of(existing)}); "
                "not loaded"
            )
            return
        found[name] = item

    def take_problems(self) -> list[str]:
        """The problems met so far, each given once."""
        taken, self.problems[:] = list(self.problems), []
        return taken
