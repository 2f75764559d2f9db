"""The classes of a generated package, read afresh for a live update
(:class:`~acordcs.runtime.live.apply_update.Classes`).

A build writes the new code of the components and monitors a changed model adds or changes (their
generated base class, and for a new one the class you implement) into the package's directory;
the running process imported the old. :meth:`PackageClasses.load` forgets the modules of those
elements and the package's ``registry`` (and ``model_types``, which the bases import), imports the
registry again (which imports them anew; the other modules stay as they are, and so do the
classes of the elements that did not change), and hands over its ``FACTORIES`` and ``MONITORS``.
The modules it replaced are kept until :meth:`keep` (the update is done) or :meth:`restore`
(rolled back: they are put back, as if nothing had been read).

The code of a component or monitor you changed in its file (``components/<C>.py``,
``monitors/<M>.py``, or the Java class of a component tagged ``language=java``) is read afresh the same way: :meth:`PackageClasses.code` gives the sha256 of
each such file as the container imported it (at start, and after each update that read it again),
which the container reports, so that ``acordcs-gen update`` finds the files changed since and plans
them (``~ code of component C``).

A module's cached bytecode is deleted before it is imported again: Python trusts a cache whose
recorded source modification time (whole seconds) and size match, and a build in the same second
can write a source of the same size.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib
import importlib.util
import os
import sys
from collections.abc import Collection, Mapping
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from acordcs.runtime.assembly import MonitorMaker
    from acordcs.runtime.live.update_steps import Factories


class PackageClasses:
    """The component and monitor classes of the generated package ``package`` (its
    ``registry``), read afresh for the elements an update adds or changes."""

    def __init__(self, package: str) -> None:
        self.package = package
        self._saved: dict[str, ModuleType | None] = {}

    def modules(self, names: Collection[str]) -> list[str]:
        """The modules read afresh for elements ``names``: theirs, the types, the registry."""
        p = self.package
        out = [f"{p}.model_types"]
        for name in names:
            out += [f"{p}.base.{name}", f"{p}.components.{name}", f"{p}.monitors.{name}"]
        return [*out, f"{p}.registry"]

    def load(self, changed: Collection[str]) -> tuple[Factories, Mapping[str, MonitorMaker]]:
        importlib.invalidate_caches()  # files the build created since the process started
        for module in self.modules(changed):
            self._saved.setdefault(module, sys.modules.pop(module, None))
            _drop_bytecode(module)
        registry = importlib.import_module(f"{self.package}.registry")
        return dict(registry.FACTORIES), dict(registry.MONITORS)

    def keep(self) -> None:
        self._saved.clear()

    def code(self, names: Collection[str]) -> dict[str, dict[str, str]]:
        """The user's file of each element of ``names`` (``components/<name>.py``, else
        ``monitors/<name>.py`` of the package; for a component tagged ``language=java``, its
        Java class ``java/<package>/<Class>.java`` beside the package) as it is now: its
        ``kind`` (component or monitor), its ``file`` (from the package's parent directory,
        ``/``-separated) and the ``sha256`` of its bytes. Called right after the classes are
        imported: what the container runs, which ``acordcs-gen update`` compares with the files
        to find changed code."""
        root = _directory(self.package)
        java = self._java_files(names) if root else {}
        out: dict[str, dict[str, str]] = {}
        for name in names:
            places = [("component", f"{self.package}/components/{name}.py"),
                      ("monitor", f"{self.package}/monitors/{name}.py")]  # fmt: skip
            if name in java:
                places = [("component", java[name])]
            for kind, file in places:
                try:
                    data = (root.parent / file).read_bytes() if root else None
                except OSError:
                    continue
                if data is not None:
                    out[name] = {
                        "kind": kind,
                        "file": file,
                        "sha256": hashlib.sha256(data).hexdigest(),
                    }
                    break
        return out

    def _java_files(self, names: Collection[str]) -> dict[str, str]:
        """The Java user files of the components of ``names`` tagged ``language=java`` (their
        language from the package's descriptor, read only when the package has Java ones)."""
        registry = sys.modules.get(f"{self.package}.registry")
        if registry is None or getattr(registry, "JAVA_SOURCES", None) is None:
            return {}
        from acordcs.java_names import identifier, package

        app = registry.descriptor()
        where = f"java/{package(app.name)}"
        return {
            c.name: f"{where}/{identifier(c.name)}.java"
            for c in app.components
            if c.language == "java" and c.name in names
        }

    def restore(self) -> None:
        for module, saved in self._saved.items():
            if saved is None:
                sys.modules.pop(module, None)
            else:
                sys.modules[module] = saved
        self._saved.clear()


def _directory(package: str) -> Path | None:
    """The directory of the imported package ``package``."""
    try:
        spec = importlib.util.find_spec(package)
    except (ImportError, ValueError):
        return None
    places = list(spec.submodule_search_locations or ()) if spec is not None else []
    return Path(places[0]) if places else None


def _drop_bytecode(module: str) -> None:
    """Delete the cached bytecode of ``module``'s source, if it is found."""
    try:
        spec = importlib.util.find_spec(module)
    except (ImportError, ValueError):
        return
    origin = spec.origin if spec is not None else None
    if not origin or not origin.endswith(".py"):
        return
    # none, or not ours to delete: Python then checks it as usual
    with contextlib.suppress(OSError):
        os.unlink(importlib.util.cache_from_source(origin))
