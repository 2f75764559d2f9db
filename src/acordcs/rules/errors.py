"""What the rule language's parsers raise: :class:`RuleSyntaxError`, an
:class:`~acordcs.errors.AcordError` whose column is in the rule text."""

from __future__ import annotations

from acordcs.errors import AcordError


class RuleSyntaxError(AcordError):
    """Rule text that does not parse; ``column`` is 1-based in the rule text."""
