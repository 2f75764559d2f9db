"""Errors of the context provider. All are :class:`~acordcs.errors.AcordError` (what, where, what to do)."""

from __future__ import annotations

from acordcs.errors import AcordError, UnreadableInputError


class ContextError(AcordError):
    """A context-provider operation that cannot be done (closed provider, broker unreachable...).

    ``file`` names the broker (``mqtt://host:port``) when there is one."""

    def location(self) -> str:
        return self.file or "context provider"


class PublishError(UnreadableInputError):
    """A published document that is refused: not XML, hostile XML, too large or too deep.

    ``file`` names the publisher, ``line``/``column`` the place in the document when the parser knows it.
    """


class SubscriptionError(AcordError):
    """An XPath expression or subscription option that is refused at subscribe (or query) time.

    ``column`` is the 1-based column in the expression when libxml2 reports one.
    """
