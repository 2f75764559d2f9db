"""Model names written into rule files: identifiers only, checked before a byte is written.

A validated model only has identifiers where rules and engines need them (N601); a build from
a descriptor made otherwise may not. A name that would reach an FCL or CLIPS file without being an
identifier is refused (code G703): quotes, parentheses, newlines or spaces in it could end a
construct early and define something the model never named.
"""

from __future__ import annotations

from collections.abc import Iterable

from acordcs.generator.errors import BuildError
from acordcs.model.generated_names import IDENTIFIER, NOT_AN_IDENTIFIER


class NameRefused(Exception):
    """A name that cannot be written: ``what`` it names, the ``name``, the element's ``id``, and
    the ``reason`` (by default: it is not an identifier)."""

    def __init__(
        self,
        what: str,
        name: object,
        element_id: str,
        qualified_name: str,
        reason: str = NOT_AN_IDENTIFIER,
    ) -> None:
        super().__init__(what)
        self.what = what
        self.name = name
        self.element_id = element_id
        self.qualified_name = qualified_name
        self.reason = reason


def require_identifiers(names: Iterable[tuple[str, object, str, str]]) -> None:
    """Raise :class:`NameRefused` for the first ``(what, name, id, qualified name)`` whose name is
    not an identifier (ASCII letters, digits and _, not starting with a digit)."""
    for what, name, element_id, qualified in names:
        if not isinstance(name, str) or not IDENTIFIER.match(name):
            raise NameRefused(what, name, element_id, qualified)


def refused(context, err: NameRefused, kind: str) -> BuildError:
    """The build error (with its G703 diagnostic) for a name refused in a ``kind`` file."""
    diagnostic = context.problem(
        "G703",
        f"{err.what} {err.name!r} cannot be written into a {kind} file: {err.reason}; rename it",
        element=err.qualified_name,
        element_id=err.element_id,
    )
    return BuildError(
        f"target {context.target}: a model name cannot be written into a {kind} file",
        diagnostics=[diagnostic],
    )
