"""What building or binding a rule engine for a policy set can fail with (besides
:class:`~acordcs.engines.rule_engine.RuleError`, a rule that cannot be defined or run). Both are
:class:`~acordcs.errors.RuntimeFailure` s: the runtime raises them to its callers as its own."""

from __future__ import annotations

from acordcs.errors import RuntimeFailure


class EngineNotAvailableError(RuntimeFailure):
    """A policy set names an engine kind no constructor is registered for."""


class BindingError(RuntimeFailure):
    """A rule variable or operation that matches no element attribute (or more than one)."""
