"""The paper's interface to rule engines: ``defrule``, ``set``, ``fire``, ``get`` (section 3).

Every engine (the fuzzy engine, CLIPS) implements :class:`RuleEngine`. Variables are model attribute
names, ``Element.attribute`` or unqualified where that is unambiguous.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from acordcs.errors import AcordError


class RuleError(AcordError):
    """A rule that cannot be defined or run: syntax, unknown variable or term.

    It names the rule set, the rule (label or index) and the column in the rule text.
    """

    def __init__(
        self,
        message: str,
        *,
        ruleset: str | None = None,
        rule: str | None = None,
        column: int | None = None,
        file: str | None = None,
        line: int | None = None,
    ) -> None:
        where = []
        if ruleset:
            where.append(f"rule set {ruleset!r}")
        if rule:
            where.append(f"rule {rule!r}")
        if column and not line:  # with a line, the column is already in file:line:col
            where.append(f"column {column}")
        element = ", ".join(where) or None
        super().__init__(message, file=file, line=line, column=column, element=element)
        self.ruleset = ruleset
        self.rule = rule


@runtime_checkable
class RuleEngine(Protocol):
    """What a policy set drives. Values are floats for fuzzy engines, any scalar for CLIPS."""

    def defrule(self, rule: str, ruleset: str) -> str:
        """Add ``rule`` to ``ruleset``, or replace the rule with the same label. Returns the label."""
        ...

    def set(self, variable: str, value: object) -> None:
        """Assert a value for a variable (an attribute of a model element)."""
        ...

    def fire(self, ruleset: str) -> None:
        """Fire the rules of ``ruleset`` on the values set so far."""
        ...

    def get(self, variable: str) -> object:
        """The current value of a variable (an output after ``fire``, or the last value set)."""
        ...
