"""The browser console a container's launcher serves beside it (``--console PORT``), found through
the table of :mod:`acordcs.plugins` by reference: the console (:mod:`acordcs.console`) is a layer
above the runtime, loaded only when a run asks for it, never imported by the runtime's modules.

The built-in entry is :func:`acordcs.console.single_process.serve_beside`; a package may declare
another under the entry point group :data:`ENTRY_POINT_GROUP`, name ``console``. What it is
called with, and what it returns, is :data:`ConsoleServer`'s.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from acordcs.plugins import PluginTable, Refused

ENTRY_POINT_GROUP = "acordcs.launcher_consoles"
BUILTIN = {"console": "acordcs.console.single_process:serve_beside"}

ConsoleServer = Callable[..., Callable[[], None]]
"""``(descriptor, container, (host, port), token, console_port, say)`` -> what stops it."""


def _accept(name: str, loaded: Any, origin: str) -> ConsoleServer:
    if not callable(loaded):
        raise Refused(f"is a {type(loaded).__name__}, not a function serving a console")
    return loaded


def console_server() -> ConsoleServer:
    """What serves the console beside a container."""
    return PluginTable(ENTRY_POINT_GROUP, "launcher console", BUILTIN, _accept).load()["console"]
