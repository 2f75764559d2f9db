"""The ACORD-CS reading of a UML model: which elements play which role, and what the relations mean.

A stereotyped element is a :class:`Role`. Relations between roles (associations of any aggregation,
dependencies, nesting, Papyrus ports) are classified by the pair of stereotypes they join, as
the README's section on modelling states: deployment, port ownership, connection ends, policy membership, adapts,
feeds and sources. This is an index over the UML view, not a second metamodel: the pyecore model is
built from it by :mod:`acordcs.model.ecore_builder` when one is needed.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from functools import cache

from acordcs.diagnostics import article, diagnostic, suggestion
from acordcs.model import causes
from acordcs.profile import PROFILE_NAME, Stereotype, profile, stereotype
from acordcs.xmi.readers.skipped import metamodel_of
from acordcs.xmi.uml import (
    Classifier,
    Element,
    Property,
    StereotypeApplication,
    UmlModel,
)

CONTAINER, COMPONENT, PORT, CONNECTION = (
    "CtxContainer",
    "CtxComponent",
    "CtxPort",
    "CtxPortConnection",
)
POLICY_SET, POLICY, MONITOR, VARIABLE = "CtxPolicySet", "CtxPolicy", "CtxMonitor", "CtxVariable"

# UML metaclass named by the profile -> element kinds it covers (a stereotype on Class also applies
# to Class's specialisations that a modeller uses for these roles).
_METACLASS_COVERS = {
    "Class": {"Class", "AssociationClass", "Component"},
    "Component": {"Component"},
    "AssociationClass": {"AssociationClass"},
    "Port": {"Port"},
    "Property": {"Property"},
}

# (stereotype a, stereotype b) -> relation name, read as "a <relation> b"
_RELATIONS = {
    (CONTAINER, COMPONENT): "hosts",
    (CONTAINER, MONITOR): "hosts",
    (CONTAINER, POLICY_SET): "hosts",
    (COMPONENT, PORT): "owns_port",
    (CONNECTION, PORT): "joins",
    (POLICY_SET, POLICY): "contains",
    (POLICY_SET, CONTAINER): "adapts",
    (POLICY_SET, COMPONENT): "adapts",
    (POLICY_SET, PORT): "adapts",
    (POLICY_SET, CONNECTION): "adapts",
    (POLICY_SET, POLICY_SET): "adapts",  # not allowed: reported as A504
    (MONITOR, POLICY_SET): "feeds",
    (MONITOR, COMPONENT): "sources",
    (MONITOR, CONTAINER): "sources",
    (MONITOR, PORT): "sources",
}


@dataclass(slots=True, eq=False)
class Role:
    """An element of the UML model that plays an ACORD-CS role."""

    stereotype: Stereotype
    element: Element
    application: StereotypeApplication
    tags: dict[str, str]

    @property
    def kind(self) -> str:
        return self.stereotype.name

    @property
    def name(self) -> str:
        return self.element.name

    @property
    def id(self) -> str:
        return self.element.id

    def tag(self, name: str) -> str | None:
        """The tag's value as written, else the profile's default.

        An empty value means unset: BOUML writes every declared tag, empty when the modeller left it.
        """
        value = self.tags.get(name)
        if value is not None and value.strip():
            return value.strip()
        declared = self.stereotype.tag(name)
        return declared.default if declared else None

    def tag_line(self, name: str) -> int:
        return self.application.tag_lines.get(name) or self.application.line or self.element.line

    def tag_column(self, name: str) -> int | None:
        """Where the file writes the tag on its line, when it says (the text notation)."""
        return self.application.tag_columns.get(name)


@dataclass(eq=False)
class Architecture:
    uml: UmlModel
    roles: dict[str, Role] = field(default_factory=dict)  # by element id
    relations: dict[str, dict[str, list[Role]]] = field(
        default_factory=lambda: defaultdict(lambda: defaultdict(list))
    )
    inverse: dict[str, dict[str, list[Role]]] = field(
        default_factory=lambda: defaultdict(lambda: defaultdict(list))
    )
    # Elements that play no role because their ACORD-CS stereotype was not read (T302 misspelt,
    # T301 on the wrong metaclass and the classifier owning such an element, R201 of an unknown
    # type, R204 applied to a misspelt id): what rules name of them is counted by that cause
    # instead of reported again (acordcs.model.causes).
    misapplied: dict[str, Element] = field(default_factory=dict)
    _by_member: dict[tuple[str, str], list[Role]] | None = field(default=None, repr=False)

    def roles_with(self, kind: str, name: str) -> list[Role]:
        """The roles whose element has an attribute (``kind`` "attribute") or an operation
        named ``name``, or (``kind`` "element") that are named ``name`` (a port also as
        ``Component.Port``); indexed on the first question, for a model's failed names."""
        if self._by_member is None:
            index: dict[tuple[str, str], list[Role]] = defaultdict(list)
            for role in self.roles.values():
                for member in getattr(role.element, "attributes", ()):
                    index[("attribute", member.name)].append(role)
                for member in getattr(role.element, "operations", ()):
                    index[("operation", member.name)].append(role)
                for shown in dict.fromkeys((role.name, self.element_name(role))):
                    index[("element", shown)].append(role)
            self._by_member = dict(index)
        return self._by_member.get((kind, name), [])

    def of_kind(self, kind: str) -> list[Role]:
        return [r for r in self.roles.values() if r.kind == kind]

    def related(self, role: Role, relation: str) -> list[Role]:
        """Roles that ``role`` <relation> (e.g. the components a container hosts)."""
        return self.relations[relation].get(role.id, [])

    def related_to(self, role: Role, relation: str) -> list[Role]:
        """Roles that <relation> ``role`` (e.g. the containers hosting a component)."""
        return self.inverse[relation].get(role.id, [])

    def attributes(self, role: Role) -> list[Property]:
        element = role.element
        return element.attributes if isinstance(element, Classifier) else []

    def variable(self, prop: Property) -> Role | None:
        role = self.roles.get(prop.id)
        return role if role is not None and role.kind == VARIABLE else None

    def scope(self, policy_set: Role) -> list[Role]:
        """Elements whose attributes the rules of ``policy_set`` may use, in a stable order."""
        seen: dict[str, Role] = {}
        for monitor in self.related_to(policy_set, "feeds"):
            seen.setdefault(monitor.id, monitor)
        for target in self.related(policy_set, "adapts"):
            seen.setdefault(target.id, target)
            if target.kind == COMPONENT:
                for port in self.related(target, "owns_port"):
                    seen.setdefault(port.id, port)
        return list(seen.values())

    def policies(self, policy_set: Role) -> list[Role]:
        return self.related(policy_set, "contains")

    def element_name(self, role: Role) -> str:
        """The name the application gives ``role``'s element: a port owned by a component as
        ``Component.Port`` (the runtime's name for it), anything else its own name."""
        if role.kind == PORT:
            owners = self.related_to(role, "owns_port")
            if owners:
                return f"{owners[0].name}.{role.name}"
        return role.name

    def _link(self, a: Role, b: Role, *, directed: bool) -> None:
        """Record the relation between ``a`` and ``b``; ``directed`` when it goes from ``a`` to ``b``
        (:func:`relation_between`)."""
        found = relation_between(a.kind, b.kind, directed=directed)
        if found is None:
            return
        relation, a_first = found
        if not a_first:
            a, b = b, a
        targets = self.relations[relation][a.id]
        if b not in targets:
            targets.append(b)
            self.inverse[relation][b.id].append(a)


def relation_between(a: str, b: str, *, directed: bool) -> tuple[str, bool] | None:
    """The relation a UML relation between elements of stereotypes ``a`` and ``b`` means, and
    whether ``a`` is its source; None when it means none. ``directed``: it goes from ``a`` to ``b``.

    Two pairs read both ways (a container and a policy set: hosts or adapts; a container and a
    monitor: hosts or sources). A relation that starts at the policy set or monitor is adapts or
    sources; any other (from the container, or undirected) is deployment.
    """
    forward = _RELATIONS.get((a, b))
    backward = _RELATIONS.get((b, a))
    if forward is None and backward is None:
        return None
    if forward is not None and backward is not None and not directed:
        return ("hosts", False) if backward == "hosts" else (forward, True)
    if forward is None:
        return backward, False  # type: ignore[return-value]
    return forward, True


STEREOTYPES = (CONTAINER, COMPONENT, PORT, CONNECTION, POLICY_SET, POLICY, MONITOR, VARIABLE)
"""The profile's stereotypes that :func:`relation_between` knows, in a stable order."""


def interpret(uml: UmlModel) -> Architecture:
    """Find the roles and classify the relations between them; diagnostics go to ``uml.diagnostics``."""
    arch = Architecture(uml)
    misplaced: list[Element] = []  # T301: a stereotype on the wrong metaclass
    for app in uml.applications.values():
        role = _role(uml, app, arch.misapplied, misplaced)
        if role is None:
            continue
        if role.id in arch.roles:
            other = arch.roles[role.id]
            uml.diagnostics.append(
                diagnostic(
                    "T301",
                    f"element has two ACORD-CS stereotypes ({other.kind} and {role.kind}); keep one",
                    file=uml.file,
                    line=role.element.line,
                    element=role.element.qualified_name(),
                    xmi_id=role.id,
                )
            )
            continue
        arch.roles[role.id] = role
    # An element with its stereotype on the wrong metaclass plays no role unless another of its
    # stereotypes gives it one; nor does the classifier owning it, unless it has one of its own
    # (the stereotype was meant for it: <<CtxComponent>> on an attribute of the component).
    for element in misplaced:
        for unread in (element, owning_classifier(element)):
            if unread is not None and unread.id not in arch.roles:
                arch.misapplied.setdefault(unread.id, unread)
    _link_relations(arch)
    return arch


def owning_classifier(element: Element) -> Classifier | None:
    """The classifier ``element`` is a member of (an attribute's, a port's, a parameter's
    operation's class), or None for a classifier or an element of no classifier."""
    if isinstance(element, Classifier):
        return None
    node = element.owner
    while node is not None and not isinstance(node, Classifier):
        node = node.owner
    return node


def _role(
    uml: UmlModel,
    app: StereotypeApplication,
    misapplied: dict[str, Element],
    misplaced: list[Element],
) -> Role | None:
    element = uml.elements[app.base]

    def report(code: str, message: str, explains: tuple[str, ...] = ()) -> None:
        uml.diagnostics.append(
            diagnostic(
                code,
                message,
                file=uml.file,
                line=app.line or element.line,
                element=element.qualified_name(),
                xmi_id=element.id,
                explains=explains,
            )
        )

    if app.profile == PROFILE_NAME:
        declared = stereotype(app.name)
        # BOUML drops stereotype properties the profile does not declare, so extra rule tags
        # (RuleSlowDown, ...) are plain key/values of the element: they belong to the stereotype.
        tags = dict(app.tags)
        if declared is not None:
            # Tags of no profile ('Rule2', or a misspelt 'frequncy') join the role, so that the tag
            # checks report the unknown ones (T303) instead of losing them; 'P:t' belongs to P.
            for key, value in element.tagged_values.items():
                if key not in tags and ":" not in key:
                    tags[key] = value
        if declared is None:
            names = [s.name for s in profile()]
            report(
                "T302",
                f"ACORDCS has no stereotype {app.name!r}{suggestion(app.name, names)}; use one of "
                f"{', '.join(names)}",
                (causes.unread(element.id),),
            )
            misapplied[element.id] = element
            return None
    elif app.profile is None and stereotype(app.name) is not None:
        # A free stereotype named like ours (older BOUML models, XMI 1.2): its element's tagged
        # values are the tags.
        declared = stereotype(app.name)
        tags = dict(element.tagged_values)
        report("R206", f"free stereotype {app.name!r} read as ACORDCS:{app.name}")
    else:
        return None
    if element.kind not in _covered(declared.metaclasses):
        if metamodel_of(element.kind) is None:
            # A type no UML version defines (uml:Clas): the reader said so (R201, an error for an
            # element with a stereotype); rules naming it are not reported again either.
            misapplied[element.id] = element
            return None
        owner = owning_classifier(element)
        explains = [causes.unread(element.id)]
        if owner is not None:
            explains.append(causes.unread(owner.id))
        if declared.name == VARIABLE:  # meant for an attribute of this classifier, or of its owner
            explains.append(causes.variable_of((owner or element).id))
        covered = _covered(declared.metaclasses)
        if declared.name == VARIABLE:
            meant = f" (an attribute of {(owner or element).name!r})"
        elif owner is not None and owner.kind in covered:
            meant = f" (perhaps {owner.name!r}, the {owner.kind} it belongs to)"
        else:
            meant = ""
        report(
            "T301",
            f"<<{declared.name}>> applies to {' or '.join(declared.metaclasses)}, not to "
            f"{article(element.kind)} {element.kind}; move the stereotype to the right "
            f"element{meant}",
            tuple(explains),
        )
        misplaced.append(element)
        return None
    return Role(declared, element, app, tags)


@cache
def _covered(metaclasses: tuple[str, ...]) -> frozenset[str]:
    """The UML metaclasses a stereotype declared on ``metaclasses`` may be applied to."""
    return frozenset().union(*(_METACLASS_COVERS.get(m, {m}) for m in metaclasses))


def _link_relations(arch: Architecture) -> None:
    uml = arch.uml
    roles = arch.roles
    for assoc in uml.associations:
        own = roles.get(assoc.id)
        ends = [
            e for e in (uml.elements.get(i) for i in assoc.member_ends) if isinstance(e, Property)
        ]
        if own is not None:  # an AssociationClass playing a role joins its ends' roles
            for end in ends:
                if end.type_ref in roles:
                    arch._link(own, roles[end.type_ref], directed=True)
            continue
        if len(ends) != 2:
            continue
        a, b = roles.get(ends[0].type_ref), roles.get(ends[1].type_ref)
        if a is None or b is None:
            continue
        # An end owned by a class is navigable from that class to the end's type.
        navigations = [
            (e.owner.id, e.type_ref)
            for e in ends
            if isinstance(e.owner, Classifier) and e.owner is not assoc
        ]
        if len(navigations) == 1 and navigations[0][0] in roles:
            source, target = navigations[0]
            arch._link(roles[source], roles[target], directed=True)
        else:
            arch._link(a, b, directed=False)
    for dep in uml.dependencies:
        for client in dep.clients:
            for supplier in dep.suppliers:
                a, b = roles.get(client), roles.get(supplier)
                if a is not None and b is not None:
                    arch._link(a, b, directed=True)
    for role in list(roles.values()):
        owner = role.element.owner
        owner_role = roles.get(owner.id) if owner is not None else None
        if owner_role is not None and role.kind != VARIABLE:  # nesting, Papyrus ports
            arch._link(owner_role, role, directed=True)
