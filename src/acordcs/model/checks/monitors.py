"""Monitors' acquisition (tag ``acquisition`` and what each kind needs) and containers' ports.

Each acquisition kind needs its own data, which the generated monitor and the runtime read:
``intercept`` a source port or component whose calls it sees; ``subscribe`` an XPath 1.0 expression
(compiled here by lxml, the engine the context provider evaluates it with); ``poll`` a frequency and
an operation of its source component that takes no input. A tag the kind does not use is a warning:
the modeller meant something the application will not do.
"""

from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from acordcs.diagnostics import Diagnostic
from acordcs.model.architecture import COMPONENT, CONTAINER, MONITOR, PORT, Role
from acordcs.model.causes import SOURCE, lacks
from acordcs.model.checks.check_context import Context
from acordcs.model.queries import (
    ACQUISITIONS,
    monitor_acquisition,
    parse_integer,
    parse_real,
    suggestion,
)

# Tags that only one acquisition kind reads.
_ONLY_FOR = {"xpath": "subscribe", "operation": "poll"}


def monitor_acquisition_data(ctx: Context) -> Iterator[Diagnostic]:
    arch = ctx.arch
    for monitor in arch.of_kind(MONITOR):
        written = monitor.tag("acquisition")
        if written and written not in ACQUISITIONS:
            continue  # T305 reports the value; the kind is unknown, so are its needs
        kind = monitor_acquisition(monitor)
        sources = arch.related(monitor, "sources")
        frequency = parse_real(monitor.tag("frequency") or "")
        for tag, user in _ONLY_FOR.items():
            if monitor.tag(tag) and kind != user:
                yield ctx.diag(
                    "A515",
                    f"monitor {monitor.name!r} acquires by {kind} and ignores its tag {tag!r} "
                    f"(read by acquisition {user}): set acquisition={user} or remove the tag",
                    monitor,
                    line=monitor.tag_line(tag),
                )
        if kind == "intercept":
            if frequency is not None:
                yield ctx.diag(
                    "A515",
                    f"monitor {monitor.name!r} intercepts calls and ignores its frequency "
                    f"({frequency:g} Hz): remove the frequency, or set acquisition=poll or custom",
                    monitor,
                    line=monitor.tag_line("frequency"),
                )
            if not any(s.kind in (PORT, COMPONENT) for s in sources):
                yield ctx.diag(
                    "A514",
                    f"monitor {monitor.name!r} intercepts calls but has no source port or "
                    "component: add a dependency from it to the <<CtxPort>> (or <<CtxComponent>>) "
                    "whose calls it sees",
                    monitor,
                    because=(lacks("sources", monitor.id, SOURCE),),
                )
        elif kind == "subscribe":
            yield from _xpath(ctx, monitor)
        elif kind == "poll":
            yield from _polled(ctx, monitor, sources, frequency)


def _xpath(ctx: Context, monitor: Role) -> Iterator[Diagnostic]:
    text = monitor.tag("xpath")
    line = monitor.tag_line("xpath")
    if not text:
        yield ctx.diag(
            "A514",
            f"monitor {monitor.name!r} subscribes to the context provider but has no tag xpath: "
            "set it to the XPath 1.0 expression selecting its documents, e.g. /telemetry",
            monitor,
            line=line,
        )
        return
    try:
        etree.XPath(text)
    except etree.XPathSyntaxError as err:
        yield ctx.diag(
            "A514",
            f"monitor {monitor.name!r}: its xpath {text!r} is not XPath 1.0 ({err}): correct it",
            monitor,
            line=line,
        )


def _polled(
    ctx: Context, monitor: Role, sources: list[Role], frequency: float | None
) -> Iterator[Diagnostic]:
    if frequency is None:
        yield ctx.diag(
            "A514",
            f"monitor {monitor.name!r} polls but has no frequency: set the tag frequency (Hz)",
            monitor,
            line=monitor.tag_line("frequency"),
        )
    components = [s for s in sources if s.kind == COMPONENT]
    if len(components) != 1:
        found = ", ".join(s.name for s in components) or "none"
        yield ctx.diag(
            "A514",
            f"monitor {monitor.name!r} polls an operation and needs exactly one source "
            f"<<CtxComponent>> (has {found}): keep one dependency to the component it polls",
            monitor,
            because=(lacks("sources", monitor.id, SOURCE),) if not components else (),
        )
        return
    component = components[0]
    name = monitor.tag("operation")
    line = monitor.tag_line("operation")
    operations = {op.name: op for op in getattr(component.element, "operations", ())}
    if not name:
        yield ctx.diag(
            "A514",
            f"monitor {monitor.name!r} polls {component.name!r} but has no tag operation: set it "
            f"to one of {', '.join(sorted(operations)) or '(the component has no operations)'}",
            monitor,
            line=line,
        )
        return
    op = operations.get(name)
    if op is None:
        yield ctx.diag(
            "A514",
            f"monitor {monitor.name!r} polls operation {name!r}, which {component.name!r} does "
            f"not have{suggestion(name, sorted(operations))}",
            monitor,
            line=line,
        )
    elif op.inputs:
        params = ", ".join(p.name for p in op.inputs)
        yield ctx.diag(
            "A514",
            f"monitor {monitor.name!r} polls {component.name}.{name}({params}), which takes "
            "input; a polled operation takes none: poll another, or use acquisition=custom",
            monitor,
            line=line,
        )


def container_ports(ctx: Context) -> Iterator[Diagnostic]:
    for container in ctx.arch.of_kind(CONTAINER):
        text = container.tag("port")
        if not text:
            continue
        port = parse_integer(text)
        if port is not None and not 1 <= port <= 65535:
            yield ctx.diag(
                "T314",
                f"container {container.name!r} has port {port}; a TCP port is 1 to 65535",
                container,
                line=container.tag_line("port"),
            )


CHECKS = (monitor_acquisition_data, container_ports)
"""This module's checks, in the order they run."""
