"""The built-in targets: ``config`` (XSLT 3.0), ``java`` (XSLT 3.0), ``python`` (XSLT 3.0, after a
check of the names in Python), ``rules`` (Python: the engines' compiled policy sets, in
:mod:`.rule_files`) and ``shell`` (XSLT 3.0, after the same check: POSIX sh scripts), named by the
table :data:`BUILTIN`; their stylesheets are in :mod:`acordcs.transforms`. :func:`targets` gives
them with the targets other packages declare as entry points of group ``acordcs.targets``."""

from __future__ import annotations

from typing import Any

from acordcs.generator.target import ENTRY_POINT_GROUP, Target, accept
from acordcs.plugins import PluginTable

BUILTIN = {
    "config": "acordcs.generator.targets.config:TARGET",
    "java": "acordcs.generator.targets.java:TARGET",
    "python": "acordcs.generator.targets.python:python",
    "rules": "acordcs.generator.targets.rule_files:rules",
    "shell": "acordcs.generator.targets.shell:shell",
}
"""The built-in targets: name -> ``"module:attribute"`` of the :class:`Target`."""


def table(**options: Any) -> PluginTable[Target]:
    """A table of the built-in targets and the entry points of :data:`ENTRY_POINT_GROUP`
    (``options``: ``entry_points``, ``extra``, as :class:`~acordcs.plugins.PluginTable` takes)."""
    return PluginTable(
        ENTRY_POINT_GROUP,
        "target",
        BUILTIN,
        accept,
        name_of=lambda name, made: made.name,
        origin_of=lambda made: made.origin,
        **options,
    )


TARGETS: PluginTable[Target] = table()
"""The targets of this process: loaded on the first :func:`targets`."""


def targets() -> dict[str, Target]:
    """Every target by name, sorted: the built-in ones and those of the entry-point group
    ``acordcs.targets`` (loaded once per process; what failed to load is in
    ``TARGETS.problems``)."""
    return TARGETS.load()
