"""What a build reports when it cannot go on: one error type, with the diagnostics that stopped it."""

from __future__ import annotations

from acordcs.diagnostics import Diagnostic
from acordcs.errors import AcordError


class BuildError(AcordError):
    """A build that stopped before writing anything: a failing target, a model name that cannot
    become a file name, an output directory that cannot be written.

    ``diagnostics`` holds the model diagnostics behind it (codes G701-G703), printed one per line as
    ``validate`` prints them; ``exit_code`` is 1 for a failure found in the model or a target, 2 for
    usage and unreadable or unwritable files.
    """

    def __init__(
        self,
        message: str,
        *,
        diagnostics: list[Diagnostic] | None = None,
        exit_code: int = 1,
        **where: object,
    ) -> None:
        super().__init__(message, **where)  # type: ignore[arg-type]
        self.diagnostics = list(diagnostics or ())
        self.exit_code = exit_code
        self.notes: list[str] = []  # what the build had to say before it stopped
