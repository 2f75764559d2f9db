"""Model checks. Each is a function ``(ctx) -> iterable of Diagnostic`` registered with :func:`check`;
:func:`run_checks` runs every one and collects all diagnostics in one pass (none stops the others).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from acordcs.diagnostics import Diagnostic, diagnostic
from acordcs.model.architecture import Architecture, Role
from acordcs.xmi.uml import Element, UmlModel

Check = Callable[["Context"], Iterable[Diagnostic]]
_CHECKS: list[Check] = []


def check(fn: Check) -> Check:
    """Register a model check."""
    _CHECKS.append(fn)
    return fn


@dataclass
class Context:
    uml: UmlModel
    arch: Architecture

    def diag(
        self,
        code: str,
        message: str,
        where: Role | Element,
        *,
        line: int | None = None,
        column: int | None = None,
        subject: str | None = None,
    ) -> Diagnostic:
        element = where.element if isinstance(where, Role) else where
        return diagnostic(
            code,
            message,
            file=self.uml.file,
            line=line or element.line,
            column=column,
            element=element.qualified_name(),
            xmi_id=element.id,
            subject=subject,
        )


def run_checks(ctx: Context) -> list[Diagnostic]:
    from acordcs.model.checks import (  # noqa: F401  (registration)
        monitors,
        names,
        profile_use,
        rules,
        structure,
        tags,
        term_limits,
    )

    out: list[Diagnostic] = []
    for fn in _CHECKS:
        try:
            out.extend(fn(ctx))
        except Exception as err:  # a bug in one check must not hide what the others find
            out.append(
                diagnostic(
                    "Z901",
                    f"check {fn.__name__} failed: {type(err).__name__}: {err}; the other checks ran",
                    file=ctx.uml.file,
                )
            )
    return out
