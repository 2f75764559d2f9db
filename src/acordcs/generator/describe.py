"""``describe(arch) -> Application``: the application descriptor of an interpreted model.

Built from the architecture index (:mod:`acordcs.model.architecture`) and the model's queries
(:mod:`acordcs.model.queries`), never from pyecore (about 40 us per object: the generator reads the
descriptor and must be fast). Meant for a model that validates without errors: an element an error
left without a place (a port of no component, a policy of no set, an element no container hosts) is
left out of the lists, and a connection without one provided and one required port of a component
raises :class:`DescriptorError`.

What each policy set's rules name is resolved here, once, by :func:`acordcs.rules.binding.bind` over
the set's scope (:func:`acordcs.model.queries.policy_scope`: the resolution the validator checked),
and written into the descriptor with each rule's label and priority, for the runtime and the
generator to read.

Order is deterministic: containers, components, connections, monitors, policy sets, ports,
policies, variables and references sorted by name, then id (references to hosted elements grouped
by kind first); properties, operations, parameters and rules stay in the model's order, which is
meaningful (declaration order, rule order).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import replace
from typing import TypeVar

from acordcs.descriptor.application import (
    Application,
    Bound,
    Component,
    Connection,
    Container,
    DescriptorError,
    End,
    Endpoint,
    Monitor,
    Operation,
    Parameter,
    Policy,
    PolicySet,
    Port,
    Property,
    Ref,
    Rule,
    Term,
    Variable,
    bound_names,
)
from acordcs.model.architecture import (
    COMPONENT,
    CONNECTION,
    CONTAINER,
    MONITOR,
    POLICY_SET,
    PORT,
    Architecture,
    Role,
)
from acordcs.model.queries import (
    monitor_acquisition,
    policy_rules,
    policy_scope,
    rule_kind,
    variable_terms,
)
from acordcs.rules import RuleSyntaxError, parse_rule
from acordcs.rules.binding import bind, default_label
from acordcs.typed_values import (
    parse_boolean,
    parse_integer,
    parse_real,
    typed_default,
    value_kind,
)
from acordcs.vocabularies import FUZZY_ENGINE
from acordcs.xmi.uml import Classifier, Element
from acordcs.xmi.uml import Operation as UmlOperation
from acordcs.xmi.uml import Property as UmlProperty

_KIND = {
    CONTAINER: "container",
    COMPONENT: "component",
    PORT: "port",
    CONNECTION: "connection",
    MONITOR: "monitor",
    POLICY_SET: "policy-set",
}
_T = TypeVar("_T")
_KIND_ORDER = {kind: n for n, kind in enumerate(_KIND.values())}

# "label: if ..." (a label is an identifier before the first ':')
_LABELLED = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*:\s*((?i:if)\b.*)$", re.S)

PYRO_OBJECT = "acordcs.container.{}"
"""The Pyro5 object name a container's server registers (``acordcs.runtime.api.container_uri`` builds its URI)."""


def describe(arch: Architecture) -> Application:
    """The descriptor of the application ``arch`` reads (see the module's docstring)."""
    return _Describer(arch).application()


# ---------------------------------------------------------------------------- remote addresses
def reached(app: Application, container: str) -> tuple[str, ...]:
    """The other containers the process of ``container`` must be given the address of
    (:attr:`Container.reaches`, as :func:`acordcs.runtime.assembly.assemble` requires them): the
    containers across a connection it calls (the required end here), or that call one of its
    ports that is not synchronous (its messages are sent back over the caller's endpoint), and
    the containers of the policy sets its monitors feed; in the order of ``app.containers``."""
    where = {r.name: c.name for c in app.containers for r in c.hosts}
    found: set[str] = set()
    for conn in app.connections:
        caller = where.get(conn.required.component)
        callee = where.get(conn.provided.component)
        if caller is None or callee is None or caller == callee:
            continue
        if caller == container:
            found.add(callee)
        elif callee == container:
            comp = next((c for c in app.components if c.name == conn.provided.component), None)
            port = comp.port(conn.provided.port) if comp is not None else None
            if port is None or port.kind != "synchronous":
                found.add(caller)
    for mon in app.monitors:
        if where.get(mon.name) != container:
            continue
        for fed in mon.feeds:
            other = where.get(fed.name)
            if other is not None and other != container:
                found.add(other)
    return tuple(c.name for c in app.containers if c.name in found)


# ------------------------------------------------------------------------------------- builder
def _order(item: object) -> tuple[str, str]:
    return (item.name, item.id)  # type: ignore[attr-defined]


def _documentation(element: Element) -> str:
    return "\n".join(c for c in element.comments if c)


class _Describer:
    def __init__(self, arch: Architecture) -> None:
        self.arch = arch
        self.file = arch.uml.file
        self._names: dict[str, str] = {}
        self._served = self._remote_containers()

    def application(self) -> Application:
        arch = self.arch
        app = Application(
            name=arch.uml.name or "application",
            containers=self._sorted(self.container(r) for r in arch.of_kind(CONTAINER)),
            components=self._sorted(self.component(r) for r in arch.of_kind(COMPONENT)),
            connections=self._sorted(self.connection(r) for r in arch.of_kind(CONNECTION)),
            monitors=self._sorted(self.monitor(r) for r in arch.of_kind(MONITOR)),
            policy_sets=self._sorted(self.policy_set(r) for r in arch.of_kind(POLICY_SET)),
        )
        return replace(
            app, containers=tuple(replace(c, reaches=reached(app, c.name)) for c in app.containers)
        )

    @staticmethod
    def _sorted(items: Iterable[_T]) -> tuple[_T, ...]:
        return tuple(sorted(items, key=_order))

    # ----------------------------------------------------------------------------- references
    def name(self, role: Role) -> str:
        """A role's resolved name: a port owned by a component as ``Component.Port``."""
        found = self._names.get(role.id)
        if found is None:
            found = self._names[role.id] = self.arch.element_name(role)
        return found

    def refs(self, roles: list[Role]) -> tuple[Ref, ...]:
        refs = {r.id: Ref(_KIND.get(r.kind, r.kind), self.name(r), r.id) for r in roles}
        return tuple(
            sorted(refs.values(), key=lambda r: (_KIND_ORDER.get(r.kind, 9), r.name, r.id))
        )

    # -------------------------------------------------------------------------------- members
    def properties(self, role: Role) -> tuple[Property, ...]:
        return tuple(self.property(role, p) for p in self.arch.attributes(role))

    def property(self, owner: Role, prop: UmlProperty) -> Property:
        var = self.arch.variable(prop)
        kind = value_kind(prop.type_name, variable=var is not None)
        range_min = (parse_real(var.tags.get("min", "")) or 0.0) if var is not None else None
        qualified = prop.qualified_name()
        try:
            default = typed_default(kind, prop.default, range_min)
        except ValueError:
            raise DescriptorError(
                f"attribute {owner.name}.{prop.name}: default {prop.default!r} is not a valid {kind} "
                f"(its type is {prop.type_name!r})",
                file=self.file,
                line=prop.line or None,
                element=f"{qualified} ({prop.id})",
                hint="fix the attribute's default value or its type in the model",
            ) from None
        return Property(
            prop.id, prop.name, qualified, prop.type_name or "", kind, default, _documentation(prop)
        )

    def operations(self, role: Role) -> tuple[Operation, ...]:
        element = role.element
        ops = element.operations if isinstance(element, Classifier) else []
        return tuple(self.operation(op) for op in ops)

    @staticmethod
    def operation(op: UmlOperation) -> Operation:
        return Operation(
            op.id,
            op.name,
            op.qualified_name(),
            tuple(Parameter(p.id, p.name, p.type_name or "", p.direction) for p in op.inputs),
            op.return_type,
            _documentation(op),
        )

    # ------------------------------------------------------------------------------- elements
    def container(self, role: Role) -> Container:
        return Container(
            role.id,
            role.name,
            role.element.qualified_name(),
            role.tag("host") or "localhost",
            self.endpoint(role),
            self.refs(self.arch.related(role, "hosts")),
            self.properties(role),
            self.operations(role),
            _documentation(role.element),
        )

    def endpoint(self, container: Role) -> Endpoint | None:
        if container.id not in self._served:
            return None
        host = container.tag("host") or "localhost"
        port = parse_integer(container.tag("port") or "")
        return Endpoint("pyro", PYRO_OBJECT.format(container.name), host, port)

    def _remote_containers(self) -> set[str]:
        """Ids of the containers that need an endpoint: those hosting a component with a port
        joined by a ``remote`` connection (each side calls or notifies the other's server)."""
        arch = self.arch
        served: set[str] = set()
        for conn in arch.of_kind(CONNECTION):
            if conn.tag("connector") != "remote":
                continue
            for port in arch.related(conn, "joins"):
                for owner in arch.related_to(port, "owns_port"):
                    served.update(c.id for c in arch.related_to(owner, "hosts"))
        return served

    def component(self, role: Role) -> Component:
        ports = self.arch.related(role, "owns_port")
        return Component(
            role.id,
            role.name,
            role.element.qualified_name(),
            role.tag("language") or "python",
            self.properties(role),
            self.operations(role),
            self._sorted(self.port(p) for p in ports),
            _documentation(role.element),
            persistent=parse_boolean(role.tag("persistent") or "") or False,
        )

    def port(self, role: Role) -> Port:
        return Port(
            role.id,
            role.name,
            role.element.qualified_name(),
            role.tag("kind") or "synchronous",
            role.tag("role") or "provided",
            self.properties(role),
            self.operations(role),
            _documentation(role.element),
        )

    def connection(self, role: Role) -> Connection:
        ends: dict[str, list[End]] = {"provided": [], "required": []}
        for port in self.arch.related(role, "joins"):
            owners = self.arch.related_to(port, "owns_port")
            side = ends.get(port.tag("role") or "provided")
            if owners and side is not None:
                side.append(End(owners[0].name, port.name, port.id))
        if len(ends["provided"]) != 1 or len(ends["required"]) != 1:
            raise DescriptorError(
                f"connection {role.name!r} joins {len(ends['required'])} required and "
                f"{len(ends['provided'])} provided ports of components; it needs one of each",
                file=self.file,
                line=role.element.line or None,
                element=f"{role.element.qualified_name()} ({role.id})",
                hint="run 'acordcs-gen validate' on the model and fix its errors (A501, A503)",
            )
        return Connection(
            role.id,
            role.name,
            role.element.qualified_name(),
            role.tag("connector") or "inprocess",
            ends["required"][0],
            ends["provided"][0],
            self.properties(role),
            self.operations(role),
            _documentation(role.element),
        )

    def monitor(self, role: Role) -> Monitor:
        acquisition = monitor_acquisition(role)
        return Monitor(
            role.id,
            role.name,
            role.element.qualified_name(),
            parse_real(role.tag("frequency") or ""),
            acquisition,
            role.tag("xpath") if acquisition == "subscribe" else None,
            role.tag("operation") if acquisition == "poll" else None,
            self.refs(self.arch.related(role, "sources")),
            self.refs(self.arch.related(role, "feeds")),
            self.properties(role),
            self.operations(role),
            _documentation(role.element),
        )

    def policy_set(self, role: Role) -> PolicySet:
        arch = self.arch
        policies = self._sorted(self.policy(p) for p in arch.policies(role))
        bound, inputs, outputs, triggers = self.bindings(role, policies)
        return PolicySet(
            role.id,
            role.name,
            role.element.qualified_name(),
            role.tag("engine") or FUZZY_ENGINE,
            role.tag("semantics") or "mamdani",
            role.tag("trigger") or "event",
            parse_real(role.tag("frequency") or ""),
            self.refs(arch.related(role, "adapts")),
            policies,
            self.variables(role),
            self.properties(role),
            self.operations(role),
            _documentation(role.element),
            bound,
            inputs,
            outputs,
            triggers,
        )

    def bindings(
        self, role: Role, policies: Iterable[Policy]
    ) -> tuple[tuple[Bound, ...], tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
        """What the set's rule names stand for (:func:`acordcs.rules.binding.bind`), the one
        resolution the validator checked, written down for the runtime and the generator."""
        kind = rule_kind(role)
        parsed = []
        for policy in policies:
            for rule in policy.rules:
                try:
                    parsed.append(parse_rule(rule.line, kind))
                except RuleSyntaxError:
                    continue  # reported by the validator (L401): the model has errors
        scope = policy_scope(self.arch, role, self.property, lambda _, op: self.operation(op))
        found = bind(scope, parsed, kind)
        return bound_names(found.targets().values()), found.inputs, found.outputs, found.triggers

    @staticmethod
    def policy(role: Role) -> Policy:
        written = []
        for rule in policy_rules(role):
            found = _LABELLED.match(rule.text)
            label, text = (found.group(1), found.group(2)) if found else (None, rule.text)
            written.append((label, text.strip(), rule.tag))
        taken = {label for label, _, _ in written if label}
        rules = []
        for position, (label, text, tag) in enumerate(written, start=1):
            if label is None:
                label = default_label(position, taken)
                taken.add(label)
                rules.append(Rule(label, text, tag, position, assigned_label=True))
            else:
                rules.append(Rule(label, text, tag, position))
        return Policy(
            role.id,
            role.name,
            role.element.qualified_name(),
            tuple(rules),
            _documentation(role.element),
        )

    def variables(self, policy_set: Role) -> tuple[Variable, ...]:
        found: dict[tuple[str, str], Variable] = {}
        for owner in self.arch.scope(policy_set):
            for prop in self.arch.attributes(owner):
                var = self.arch.variable(prop)
                if var is None or (owner.id, prop.id) in found:
                    continue
                terms = tuple(
                    Term(t.name.text, t.shape, tuple(float(p) for p in t.parameters))
                    for t in variable_terms(var)
                )
                found[owner.id, prop.id] = Variable(
                    prop.id,
                    self.name(owner),
                    prop.name,
                    prop.qualified_name(),
                    parse_real(var.tags.get("min", "")) or 0.0,
                    parse_real(var.tags.get("max", "")) or 0.0,
                    terms,
                )
        return tuple(sorted(found.values(), key=lambda v: (v.name, v.id)))
