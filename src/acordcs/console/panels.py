"""Panels an application adds to the console's page, registered one way: the table of
:mod:`acordcs.plugins` (acordcs has no built-in panel; other packages declare entry points of
:data:`ENTRY_POINT_GROUP`; a script or a test gives its own as ``extra``), never by being
imported.

A :class:`ConsolePanel` is what only that application has (the WebLab's cameras, map and
teleoperation): its static files (an ES module the page imports, exporting ``mount(section,
console)``, and a style sheet), the commands it adds (read strictly by its own ``parse``), its
binary channels and paced commands, and ``attach``: what makes its :class:`PanelSession` over the
application the console attached to. The page around it is the console's: the architecture,
context, policies, events and hands, the token, the checks and the slots.

A panel session gets what the containers' watches deliver (``deliver``, from their threads), may
ask for the calls of operations to be watched (``calls``), publishes on the console's hub, and
answers its commands (a method of its name). It never attaches by itself: the console's
:class:`~acordcs.console.attaching.Application` is given to it, with the console's token.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from importlib.resources.abc import Traversable
from typing import TYPE_CHECKING, Any, Protocol

from acordcs.plugins import PluginTable, Refused

if TYPE_CHECKING:
    from acordcs.console.attaching import Application
    from acordcs.console.fanout import ConsoleHub
    from acordcs.console.viewer_messages import Command
    from acordcs.descriptor import Application as AppDescriptor

ENTRY_POINT_GROUP = "acordcs.console_panels"

BUILTIN: dict[str, str] = {}
"""acordcs's own panels: none (a panel is what one application only has)."""


class PanelSession(Protocol):
    """A panel over the running application (see the module docstring); its commands are its
    methods of their names. Each method here is optional (a panel that only answers commands
    needs none)."""

    def calls(self) -> Mapping[str, list[str]]:
        """Container -> the operations (``Component.operation``) whose calls it watches."""
        ...

    def begin(self) -> None:
        """The watches run: begin (AttachError when the application refuses the panel)."""
        ...

    def deliver(self, kind: str, container: str, data: Any) -> None: ...

    def close(self) -> None: ...


@dataclass(frozen=True)
class PanelContext:
    """What a panel session is given: the console's ``hub`` and ``token``, the ``app`` it is
    attached to."""

    hub: ConsoleHub
    token: str
    app: Application


@dataclass(frozen=True)
class ConsolePanel:
    """One application's panel (see the module docstring). ``applies``: whether it belongs on
    the console of an application (its descriptor); ``commands``: the names ``parse`` reads (none
    of the console's own); ``script`` and ``style``: files of ``static``, served under
    ``/panels/<name>/``."""

    name: str
    title: str
    static: Traversable
    applies: Callable[[AppDescriptor], bool]
    attach: Callable[[PanelContext], PanelSession]
    parse: Callable[[str | bytes], Command] | None = None
    commands: frozenset[str] = frozenset()
    binary_channels: Mapping[str, int] = field(default_factory=dict)
    paced: Mapping[str, int] = field(default_factory=dict)
    script: str = "panel.js"
    style: str | None = "panel.css"

    def shown(self) -> dict[str, Any]:
        """What the page is told of it (in ``hello``): where its module and style are."""
        base = f"/panels/{self.name}/"
        return {
            "name": self.name,
            "title": self.title,
            "script": base + self.script,
            "style": base + self.style if self.style else None,
        }


CONSOLE_COMMANDS = frozenset(("ping", "auth", "call", "set", "plan", "apply"))


def _accept(name: str, loaded: Any, origin: str) -> ConsolePanel:
    if not isinstance(loaded, ConsolePanel):
        raise Refused(f"is a {type(loaded).__name__}, not an acordcs.console.panels.ConsolePanel")
    taken = loaded.commands & CONSOLE_COMMANDS
    if taken:
        raise Refused(f"names the console's own commands {', '.join(sorted(taken))}: rename them")
    return loaded


def panel_table(**options: Any) -> PluginTable[ConsolePanel]:
    """The panels: the entry points of :data:`ENTRY_POINT_GROUP`, plus ``extra`` ones."""
    return PluginTable(
        ENTRY_POINT_GROUP, "console panel", BUILTIN, _accept,
        name_of=lambda name, item: item.name, **options,
    )  # fmt: skip


def panels_for(descriptor: AppDescriptor, table: PluginTable[ConsolePanel]) -> list[ConsolePanel]:
    """The panels of ``table`` that belong on the console of ``descriptor``'s application."""
    return [p for p in table.load().values() if p.applies(descriptor)]
