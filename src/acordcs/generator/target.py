"""Targets by name: Python functions and XSLT stylesheets behind one signature.

A target is run as ``target.run(context)`` (:class:`~acordcs.generator.target_context.TargetContext`):

- a Python target is a function ``def my_target(context) -> None`` that calls ``context.emit``,
  registered with the :func:`target` decorator;
- an XSLT 3.0 target is a stylesheet run by Saxon over the descriptor XML (:func:`xslt_target`):
  its result documents are the files; its principal result is empty, or a listing that says
  more of them (:mod:`.xslt`).

The built-in targets are the table :data:`acordcs.generator.targets.BUILTIN`; other packages add
theirs through the
entry-point group ``acordcs.targets`` (``name = "package.module:attribute"``, the attribute a
target made by :func:`target` or :func:`xslt_target`, or any function with the target signature),
loaded by :mod:`acordcs.plugins` (:func:`accept` says what such an attribute may be). Making a target registers nothing: a target exists because the
table or an entry point names it.
"""

from __future__ import annotations

import hashlib
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from acordcs.diagnostics import article
from acordcs.plugins import Refused

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
    trusted: bool = (
        False  # a stylesheet run with the user's rights (--trust-stylesheet), not confined
    )

    @property
    def kind(self) -> str:
        return "xslt" if self.stylesheet is not None else "python"

    def run(self, context: object) -> None:
        """Run the target: every file it makes is emitted into ``context``."""
        if self.stylesheet is not None:
            from acordcs.generator.xslt import run_stylesheet

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


def target(
    name: str, *, description: str = "", version: str = ""
) -> Callable[[TargetFunction], Target]:
    """Make the decorated function ``f(context) -> None`` the Python target ``name`` (a
    :class:`Target`; an entry point of group ``acordcs.targets`` naming it makes it available).

    ::

        from acordcs.generator import target

        @target("summary", description="one line per component")
        def summary(context):
            lines = [c.name for c in context.application.components]
            context.emit("summary.txt", context.header("hash", "the model") + "\\n".join(lines) + "\\n")
    """
    check_name(name)

    def make(function: TargetFunction) -> Target:
        doc = (function.__doc__ or "").strip().splitlines()
        return Target(
            name,
            description or (doc[0] if doc else name),
            function=function,
            origin=_origin(function.__module__),
            version=version,
        )

    return make


def xslt_target(
    name: str, stylesheet: str | Path, *, description: str = "", version: str = ""
) -> Target:
    """The XSLT 3.0 stylesheet at ``stylesheet`` (a file path; for package data, e.g.
    ``importlib.resources.files(__package__) / "my.xsl"``) as target ``name``. Its origin is
    ``acordcs`` for a stylesheet of :mod:`acordcs.transforms`, else that of the entry point that
    names it."""
    check_name(name)
    path = Path(str(stylesheet))
    return Target(
        name,
        description or name,
        stylesheet=path,
        origin="acordcs" if path.resolve().parent == _TRANSFORMS else "?",
        version=version,
    )


_TRANSFORMS = Path(__file__).resolve().parent.parent / "transforms"


def _origin(module: str) -> str:
    return "acordcs" if module.split(".", 1)[0] == "acordcs" else module or "?"


def check_name(name: object) -> None:
    """A ValueError unless ``name`` can name a target (:data:`NAME_PATTERN`, not ``all``)."""
    if not isinstance(name, str) or not NAME_PATTERN.match(name) or name == "all":
        raise ValueError(
            f"{name!r} cannot name a target: use letters, digits, '_', '.' and '-' (not 'all')"
        )


def accept(name: str, loaded: Any, origin: str) -> Target:
    """What a table's reference or an entry point names, as a target from ``origin``."""
    if isinstance(loaded, Target):
        return loaded if origin == "acordcs" else replace(loaded, origin=origin)
    if callable(loaded):
        try:
            check_name(name)
        except ValueError as err:  # a plug-in's entry point named like no target can be
            raise Refused(f"names no target: {err}") from None
        doc = (loaded.__doc__ or "").strip().splitlines()
        return Target(name, doc[0] if doc else name, function=loaded, origin=origin)
    raise Refused(
        f"is {article(type(loaded).__name__)} {type(loaded).__name__}, not a target; point it at "
        "a function decorated with acordcs.generator.target or made by xslt_target"
    )
