"""The one error type users see, textX style: it carries file, line and column, and an exit code.

Formatting a message (``str(err)``) is apart from showing it (the CLI decides where it goes).
"""

from __future__ import annotations


class AcordError(Exception):
    """An error in user input: a model, a rule, an FCL file, a command line.

    ``exit_code`` follows the CLI convention: 1 a failure found in valid input, 2 usage or unreadable input.
    """

    exit_code = 1

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        line: int | None = None,
        column: int | None = None,
        element: str | None = None,
        hint: str | None = None,
    ) -> None:
        super().__init__(message)
        self.message = message
        self.file = file
        self.line = line
        self.column = column
        self.element = element
        self.hint = hint

    def location(self) -> str:
        parts = [self.file or "<input>"]
        if self.line:
            parts.append(str(self.line))
            if self.column:
                parts.append(str(self.column))
        return ":".join(parts)

    def __str__(self) -> str:
        text = f"{self.location()}: error: {self.message}"
        if self.element:
            text += f" [{self.element}]"
        if self.hint:
            text += f" ({self.hint})"
        return text


class UnreadableInputError(AcordError):
    """Input that cannot be read at all: missing file, not XML, hostile XML."""

    exit_code = 2


class RuntimeFailure(AcordError):
    """Base of every error raised while an application runs (the runtime's, the engines'). ``where`` names the container (or connector) it happened in."""

    def __init__(self, message: str, *, where: str | None = None, hint: str | None = None) -> None:
        super().__init__(message, element=None, hint=hint)
        self.where = where

    def location(self) -> str:
        return self.where or "runtime"


class ConfigurationError(RuntimeFailure, ValueError):
    """A setting out of its domain: a period or timeout <= 0, a periodic policy set without
    frequency, an attribute default that is not of its type. Also a ValueError."""
