"""Targets by name: Python functions and XSLT stylesheets behind one signature.

A target is run as ``target.run(context)`` (:class:`~acordcs.codegen.context.TargetContext`):

- a Python target is a function ``def my_target(context) -> None`` that calls ``context.emit``,
  registered with the :func:`target` decorator;
- an XSLT 3.0 target is a stylesheet run by Saxon over the descriptor XML (:func:`xslt_target`):
  its result documents are the files, its principal result lists them (:mod:`.xslt`).

Built-in targets are listed in :mod:`acordcs.codegen.targets`; other packages add theirs through
the entry-point group ``acordcs.targets`` (``name = "package.module:attribute"``, the attribute a
target made by :func:`target` or :func:`xslt_target`, or any function with the target signature).
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

ENTRY_POINT_GROUP = "acordcs.targets"
NAME_PATTERN = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*\Z")
"""What a target's name is: letters, digits, ``_``, ``.`` and ``-``, not starting with ``.`` or ``-``."""

TargetFunction = Callable[..., None]


@dataclass(frozen=True)
class Target:
    """A registered target. Exactly one of ``function`` (Python) and ``stylesheet`` (a path to an
    XSLT 3.0 file) is set. ``origin`` says where it comes from (``acordcs`` or a distribution),
    ``version`` is part of its fingerprint (see :meth:`fingerprint`)."""

    name: str
    description: str
    function: TargetFunction | None = None
    stylesheet: Path | None = None
    origin: str = "acordcs"
    version: str = ""

    @property
    def kind(self) -> str:
        return "xslt" if self.stylesheet is not None else "python"

    def run(self, context: object) -> None:
        """Run the target: every file it makes is emitted into ``context``."""
        if self.stylesheet is not None:
            from acordcs.codegen.xslt import run_stylesheet

            run_stylesheet(self, context)  # type: ignore[arg-type]
        else:
            assert self.function is not None
            self.function(context)

    def __call__(self, context: object) -> None:
        self.run(context)

    def code_files(self) -> list[Path]:
        """The files whose content decides what this target writes, besides the toolchain itself:
        its stylesheet, or the module defining its function."""
        if self.stylesheet is not None:
            return [self.stylesheet]
        module = sys.modules.get(getattr(self.function, "__module__", ""), None)
        path = getattr(module, "__file__", None)
        return [Path(path)] if path else []

    def fingerprint(self, toolchain: str) -> str:
        """A digest of what makes this target's output: the toolchain's own digest, the target's
        name, version and code files. Same fingerprint and same model: same output."""
        digest = hashlib.sha256(f"{toolchain}\0{self.name}\0{self.version}\0".encode())
        for path in self.code_files():
            try:
                digest.update(path.read_bytes())
            except OSError:
                digest.update(b"?")
        return digest.hexdigest()


_REGISTRY: dict[str, Target] = {}
_LOADED = False
PROBLEMS: list[str] = []
"""Entry points that could not be loaded, as messages (the CLI prints them as warnings)."""


def target(
    name: str, *, description: str = "", version: str = ""
) -> Callable[[TargetFunction], Target]:
    """Register the decorated function ``f(context) -> None`` as the Python target ``name``.

    ::

        from acordcs.codegen import target

        @target("summary", description="one line per component")
        def summary(context):
            lines = [c.name for c in context.application.components]
            context.emit("summary.txt", context.header("hash", "the model") + "\\n".join(lines) + "\\n")
    """

    def register_function(function: TargetFunction) -> Target:
        doc = (function.__doc__ or "").strip().splitlines()
        made = Target(
            name,
            description or (doc[0] if doc else name),
            function=function,
            origin=_origin(function.__module__),
            version=version,
        )
        register(made)
        return made

    return register_function


def xslt_target(
    name: str, stylesheet: str | Path, *, description: str = "", version: str = ""
) -> Target:
    """Register the XSLT 3.0 stylesheet at ``stylesheet`` (a file path; for package data, e.g.
    ``importlib.resources.files(__package__) / "my.xsl"``) as target ``name``."""
    caller = sys._getframe(1).f_globals.get("__name__", "")
    made = Target(
        name,
        description or name,
        stylesheet=Path(str(stylesheet)),
        origin=_origin(caller),
        version=version,
    )
    register(made)
    return made


def _origin(module: str) -> str:
    return "acordcs" if module.split(".", 1)[0] == "acordcs" else module or "?"


def _same(a: Target, b: Target) -> bool:
    return a.function is b.function and a.stylesheet == b.stylesheet


def register(made: Target) -> Target:
    """Add a target (the decorators call this); a name already taken by another target is a
    ValueError."""
    if not isinstance(made.name, str) or not NAME_PATTERN.match(made.name) or made.name == "all":
        raise ValueError(
            f"{made.name!r} cannot name a target: use letters, digits, '_', '.' and '-' (not 'all')"
        )
    old = _REGISTRY.get(made.name)
    if old is not None and not _same(old, made):
        raise ValueError(
            f"target {made.name!r} is already registered ({old.origin}); choose another name"
        )
    _REGISTRY[made.name] = made
    return made


def unregister(name: str) -> None:
    """Remove a target (tests, and scripts replacing one)."""
    _REGISTRY.pop(name, None)


def targets() -> dict[str, Target]:
    """Every registered target by name, sorted: the built-in ones and those of the entry-point
    group ``acordcs.targets`` (loaded once per process; what failed to load is in :data:`PROBLEMS`)."""
    global _LOADED
    if not _LOADED:
        _LOADED = True
        import acordcs.codegen.targets  # noqa: F401  (registers the built-in targets)

        _load_entry_points()
    return dict(sorted(_REGISTRY.items()))


def reload() -> dict[str, Target]:
    """Read the entry points again (after installing a package, or in tests)."""
    global _LOADED
    _LOADED = False
    PROBLEMS.clear()
    for name in [n for n, t in _REGISTRY.items() if t.origin != "acordcs"]:
        del _REGISTRY[name]
    return targets()


def _declared_somewhere() -> bool:
    """Whether some distribution on sys.path may declare entry points of the group: a look at
    the ``entry_points.txt`` files of the ``*.dist-info`` and ``*.egg-info`` directories, which
    spares every build that has no plug-in the 15 ms importlib.metadata takes to import. True
    (ask importlib.metadata) whenever a path entry is not a plain directory (a zip, an egg)."""
    header = f"[{ENTRY_POINT_GROUP}]".encode()
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


def _entry_points() -> list:
    """The entry points of group ``acordcs.targets`` (importlib.metadata)."""
    if not _declared_somewhere():
        return []
    from importlib import metadata

    return list(metadata.entry_points(group=ENTRY_POINT_GROUP))


def _load_entry_points() -> None:
    for point in _entry_points():
        dist = getattr(getattr(point, "dist", None), "name", None) or "an installed package"
        where = f"entry point {point.name} = {point.value} (from {dist}, group {ENTRY_POINT_GROUP})"
        try:
            loaded = point.load()
        except Exception as err:  # a broken plug-in must not stop the others
            PROBLEMS.append(
                f"{where} could not be loaded: {type(err).__name__}: {err}; "
                "fix or uninstall that package"
            )
            continue
        if isinstance(loaded, Target):
            made = loaded
            if made.name != point.name:
                PROBLEMS.append(
                    f"{where} is target {made.name!r}: registered as {made.name!r}; "
                    "give the entry point the target's name"
                )
        elif callable(loaded):
            doc = (loaded.__doc__ or "").strip().splitlines()
            made = Target(point.name, doc[0] if doc else point.name, function=loaded, origin=dist)
        else:
            PROBLEMS.append(
                f"{where} is a {type(loaded).__name__}, not a target; point it at a function "
                "decorated with acordcs.codegen.target or made by xslt_target"
            )
            continue
        existing = _REGISTRY.get(made.name)
        if existing is not None and not _same(existing, made):
            PROBLEMS.append(
                f"{where}: target {made.name!r} already exists ({existing.origin}); not loaded"
            )
            continue
        _REGISTRY[made.name] = replace(made, origin=dist)
