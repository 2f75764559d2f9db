"""Errors of the component provider: what, where (description file and line, or URL), what to do."""

from __future__ import annotations

from acordcs.errors import AcordError


class RepositoryError(AcordError):
    """A malformed description, a failed search, or a factory package that cannot be installed.

    Whenever it is raised by an installation, nothing was installed and nothing was left behind.
    """
