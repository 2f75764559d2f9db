"""What every model check gets: the UML view and its ACORD-CS reading, and a way to make a
diagnostic located at a model element."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from acordcs.diagnostics import Diagnostic, diagnostic
from acordcs.model.architecture import Architecture, Role
from acordcs.xmi.uml import Element, UmlModel

Check = Callable[["Context"], Iterable[Diagnostic]]
"""A model check: a function of the context giving its diagnostics."""


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
        because: tuple[str, ...] = (),
    ) -> Diagnostic:
        """``code`` at ``where``; ``because``: the keys of the causes that would explain it
        (:mod:`acordcs.model.causes`)."""
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
            because=because,
        )
