"""Model checks. Each is a function ``(ctx) -> iterable of Diagnostic`` (:data:`~.context.Check`,
its context :class:`~.context.Context`); :func:`run_checks` runs every one and collects all
diagnostics in one pass (none stops the others).

The built-in checks are the table :data:`BUILTIN` (each module's ``CHECKS``); other packages add
theirs through the entry-point group ``acordcs.checks`` (``name = "package.module:attribute"``, a
check function or a tuple of them), loaded by :mod:`acordcs.plugins`.
"""

from __future__ import annotations

from typing import Any

from acordcs.diagnostics import Diagnostic, article, diagnostic
from acordcs.model.checks.check_context import Check, Context
from acordcs.plugins import PluginTable, Refused

ENTRY_POINT_GROUP = "acordcs.checks"

BUILTIN = {
    "monitors": "acordcs.model.checks.monitors:CHECKS",
    "names": "acordcs.model.checks.element_names:CHECKS",
    "profile_use": "acordcs.model.checks.profile_use:CHECKS",
    "rules": "acordcs.model.checks.rule_checks:CHECKS",
    "structure": "acordcs.model.checks.structure:CHECKS",
    "tags": "acordcs.model.checks.tags:CHECKS",
    "term_limits": "acordcs.model.checks.term_limits:CHECKS",
}
"""The built-in checks: name -> ``"module:attribute"`` of a tuple of checks, run in this order."""


def _accept(name: str, loaded: Any, origin: str) -> tuple[Check, ...]:
    found = tuple(loaded) if isinstance(loaded, (tuple, list)) else (loaded,)
    if not found or not all(callable(fn) for fn in found):
        raise Refused(
            f"is {article(type(loaded).__name__)} {type(loaded).__name__}, not a check; point it "
            "at a function taking the check context, or a tuple of them"
        )
    return found


def table(**options: Any) -> PluginTable[tuple[Check, ...]]:
    """A table of the built-in checks and the entry points of :data:`ENTRY_POINT_GROUP`
    (``options``: ``entry_points``, ``extra``, as :class:`~acordcs.plugins.PluginTable` takes)."""
    return PluginTable(ENTRY_POINT_GROUP, "check", BUILTIN, _accept, **options)


CHECKS: PluginTable[tuple[Check, ...]] = table()
"""The checks of this process: loaded on the first :func:`run_checks`."""


def run_checks(ctx: Context) -> list[Diagnostic]:
    """Every check's diagnostics; a check that raises gives Z901 and the others run, a plug-in
    check that could not be loaded Z902."""
    table = CHECKS.load()
    out = [diagnostic("Z902", problem, file=ctx.uml.file) for problem in CHECKS.problems]
    for name in (*BUILTIN, *(n for n in table if n not in BUILTIN)):
        for fn in table[name]:
            try:
                out.extend(fn(ctx))
            except Exception as err:  # a bug in one check must not hide what the others find
                out.append(
                    diagnostic(
                        "Z901",
                        f"check {fn.__name__} failed: {type(err).__name__}: {err}; the other "
                        "checks ran",
                        file=ctx.uml.file,
                    )
                )
    return out


__all__ = ["BUILTIN", "CHECKS", "ENTRY_POINT_GROUP", "Check", "Context", "run_checks", "table"]
