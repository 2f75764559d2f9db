"""Architecture: connections, what policy sets adapt, monitors feeding sets, deployment, membership."""

from __future__ import annotations

from collections.abc import Iterator

from acordcs.diagnostics import Diagnostic, article
from acordcs.model.architecture import (
    COMPONENT,
    CONNECTION,
    CONTAINER,
    MONITOR,
    POLICY,
    POLICY_SET,
    PORT,
    Role,
)
from acordcs.model.causes import SOURCE, TARGET, lacks, unread
from acordcs.model.checks.check_context import Context
from acordcs.typed_values import parse_boolean

_ADAPTABLE = {CONTAINER, COMPONENT, PORT, CONNECTION}


def connections(ctx: Context) -> Iterator[Diagnostic]:
    arch = ctx.arch
    for conn in arch.of_kind(CONNECTION):
        ports = arch.related(conn, "joins")
        yield from _unowned_ends(ctx, conn, ports)
        yield from _deployed_apart(ctx, conn, ports)
        if len(ports) != 2:
            names = ", ".join(p.name for p in ports) or "none"
            yield ctx.diag(
                "A503",
                f"port connection {conn.name!r} joins {len(ports)} port(s) ({names}); relate it to "
                "exactly two <<CtxPort>> elements (ports of components)",
                conn,
                because=(lacks("joins", conn.id, SOURCE),) if len(ports) < 2 else (),
            )
            continue
        a, b = ports
        roles = {a.tag("role"), b.tag("role")}
        if roles != {"provided", "required"}:
            yield ctx.diag(
                "A501",
                f"port connection {conn.name!r} joins {a.name!r} ({a.tag('role')}) and {b.name!r} "
                f"({b.tag('role')}); it must join a provided and a required port",
                conn,
            )
        if a.tag("kind") != b.tag("kind"):
            yield ctx.diag(
                "A502",
                f"port connection {conn.name!r} joins {_a(a.tag('kind'))} port ({a.name!r}) and "
                f"{_a(b.tag('kind'))} port ({b.name!r}); both must be of the same kind: set the tag "
                "kind of one to the other's",
                conn,
            )


def policy_sets(ctx: Context) -> Iterator[Diagnostic]:
    arch = ctx.arch
    for ps in arch.of_kind(POLICY_SET):
        for target in arch.related(ps, "adapts"):
            if target.kind not in _ADAPTABLE:
                yield ctx.diag(
                    "A504",
                    f"policy set {ps.name!r} is related to {target.kind} {target.name!r}; a policy set "
                    "adapts containers, components, ports and port connections",
                    ps,
                )
        if not arch.policies(ps):
            yield ctx.diag(
                "A509",
                f"policy set {ps.name!r} has no policies: relate <<CtxPolicy>> classes to it",
                ps,
                because=(lacks("contains", ps.id, SOURCE),),
            )
        if not arch.related(ps, "adapts") and not arch.related_to(ps, "feeds"):
            yield ctx.diag(
                "A513",
                f"policy set {ps.name!r} adapts nothing and no monitor feeds it: its rules can refer "
                "to no variable",
                ps,
                because=(lacks("adapts", ps.id, SOURCE), lacks("feeds", ps.id, TARGET)),
            )
        if ps.tag("trigger") == "periodic" and not ps.tags.get("frequency", "").strip():
            yield ctx.diag(
                "A510",
                f"policy set {ps.name!r} is periodic but has no frequency: set the tag frequency (Hz)",
                ps,
            )
    for policy in arch.of_kind(POLICY):
        owners = arch.related_to(policy, "contains")
        if len(owners) != 1:
            names = ", ".join(o.name for o in owners)
            msg = (
                f"policy {policy.name!r} belongs to no policy set: relate it to one <<CtxPolicySet>>"
                if not owners
                else f"policy {policy.name!r} belongs to {len(owners)} policy sets ({names}); keep one"
            )
            yield ctx.diag(
                "A508",
                msg,
                policy,
                because=(lacks("contains", policy.id, TARGET),) if not owners else (),
            )


def monitors(ctx: Context) -> Iterator[Diagnostic]:
    for monitor in ctx.arch.of_kind(MONITOR):
        if not ctx.arch.related(monitor, "feeds"):
            yield ctx.diag(
                "A505",
                f"monitor {monitor.name!r} feeds no policy set: relate it to the <<CtxPolicySet>> that "
                "uses its attributes",
                monitor,
                because=(lacks("feeds", monitor.id, SOURCE),),
            )


def deployment(ctx: Context) -> Iterator[Diagnostic]:
    arch = ctx.arch
    for kind in (COMPONENT, MONITOR, POLICY_SET):
        for role in arch.of_kind(kind):
            hosts = arch.related_to(role, "hosts")
            if not hosts:
                yield ctx.diag(
                    "A506",
                    f"{kind} {role.name!r} is not deployed: relate it to the <<CtxContainer>> that hosts it",
                    role,
                    because=(lacks("hosts", role.id, TARGET),),
                )
            elif len(hosts) > 1:
                names = ", ".join(h.name for h in hosts)
                yield ctx.diag(
                    "A507",
                    f"{kind} {role.name!r} is deployed in {len(hosts)} containers ({names}); keep one",
                    role,
                )


def ports(ctx: Context) -> Iterator[Diagnostic]:
    for port in ctx.arch.of_kind(PORT):
        owners = ctx.arch.related_to(port, "owns_port")
        if not owners:
            yield ctx.diag(
                "A511",
                f"port {port.name!r} belongs to no component: relate it to one",
                port,
                because=_unowned(port),
            )
        elif len(owners) > 1:
            names = ", ".join(o.name for o in owners)
            yield ctx.diag(
                "A512",
                f"port {port.name!r} belongs to {len(owners)} components ({names}); keep one",
                port,
            )


def _unowned(port: Role) -> tuple[str, ...]:
    """What would explain that ``port`` belongs to no component: a lost relation to its
    component, or the class owning it (a Papyrus port's) not read as one."""
    owner = port.element.owner
    keys = (lacks("owns_port", port.id, TARGET),)
    return (*keys, unread(owner.id)) if owner is not None else keys


def _a(word: str | None) -> str:
    word = word or "unset"
    return f"{article(word)} {word}"


def _unowned_ends(ctx: Context, conn: Role, ports: list[Role]) -> Iterator[Diagnostic]:
    """A517: a joined port that belongs to no component. A port alone may (A511, a warning), but a
    connection's end is a component's port: the descriptor, and every generated file, name it so."""
    for port in ports:
        if not ctx.arch.related_to(port, "owns_port"):
            yield ctx.diag(
                "A517",
                f"port connection {conn.name!r} joins port {port.name!r}, which belongs to no "
                "component: a connection joins ports of components; relate the port to the "
                "<<CtxComponent>> that owns it (Papyrus: make it a uml:Port of the component)",
                conn,
                subject=port.name,
                because=_unowned(port),
            )


def _deployed_apart(ctx: Context, conn: Role, ports: list[Role]) -> Iterator[Diagnostic]:
    """A516: a connector the deployment cannot honour. The generated deployment runs each container
    in a process of its own (bin/<C>-start), so an ``inprocess`` connection, a direct call in one
    process, cannot join components of two containers; ``remote`` and ``shaped`` go over the
    containers' endpoints there (and stay direct calls within one container)."""
    if conn.tag("connector") != "inprocess" or len(ports) != 2:
        return
    placed = []
    for port in ports:
        owners = ctx.arch.related_to(port, "owns_port")
        hosts = ctx.arch.related_to(owners[0], "hosts") if len(owners) == 1 else []
        if len(hosts) != 1:
            return  # reported as A511/A517, A506 or A507: where it runs is unknown
        placed.append((owners[0], port, hosts[0]))
    (comp_a, port_a, host_a), (comp_b, port_b, host_b) = placed
    if host_a.id == host_b.id:
        return

    def where(comp: Role, port: Role, host: Role) -> str:
        return f"{comp.name}.{port.name} (container {host.name!r}, host {host.tag('host')!r})"

    written = (
        "its tag connector is 'inprocess'"
        if conn.tags.get("connector", "").strip()
        else ("its tag connector is unset, which means 'inprocess'")
    )
    yield ctx.diag(
        "A516",
        f"port connection {conn.name!r} is in-process ({written}) but joins "
        f"{where(comp_a, port_a, host_a)} and {where(comp_b, port_b, host_b)}: each container runs "
        "in a process of its own, which an in-process call cannot leave; set the tag connector to "
        "remote (or shaped), or deploy both components in one container",
        conn,
        line=conn.tag_line("connector"),
        subject="connector",
    )


def persistence(ctx: Context) -> Iterator[Diagnostic]:
    """A518: a component tagged ``persistent`` that declares no property. Its container keeps the
    properties the model declares and the state fields its class names (``state_fields``), which
    the model cannot see: the tag may keep nothing."""
    for comp in ctx.arch.of_kind(COMPONENT):
        if not parse_boolean(comp.tag("persistent") or "") or ctx.arch.attributes(comp):
            continue
        yield ctx.diag(
            "A518",
            f"component {comp.name!r} is tagged persistent but declares no property: its container "
            "keeps only the state fields its class names (state_fields), if any; give it the "
            "attributes whose values must survive a restart, or remove the tag",
            comp,
            line=comp.tag_line("persistent"),
            column=comp.tag_column("persistent"),
            subject="persistent",
        )


CHECKS = (connections, policy_sets, monitors, deployment, ports, persistence)
"""This module's checks, in the order they run."""
