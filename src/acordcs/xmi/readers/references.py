"""What the XMI 2.x reader does once the walk is over: every id a read element names resolved
against the file (types, references, association ends, comments' annotated elements, stereotype
applications), and what is not in the file said as it matters to ACORD-CS (R202 an error when an
ACORD-CS element makes or is joined by the reference, else a warning; R203, R204); and, for an
element the walk skips (R201), what ACORD-CS would read in it.

:class:`References` is a part of the reader (:class:`acordcs.xmi.readers.xmi2._Reader`): it works on
the reader's model, its collected references and its stereotype applications.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from lxml import etree

from acordcs.diagnostics import diagnostic
from acordcs.profile import PROFILE_NAME
from acordcs.xmi.readers import unread
from acordcs.xmi.readers.common import (
    acordcs_roles,
    check_ids,
    dangling,
    described,
    relates,
    touched,
)
from acordcs.xmi.readers.stereotypes import local_name
from acordcs.xmi.uml import Dependency, Element, Property

if TYPE_CHECKING:
    from acordcs.xmi.readers.stereotypes import StereotypeApplications
    from acordcs.xmi.source import XmlInput
    from acordcs.xmi.uml import UmlModel


class References:
    """The resolution half of the XMI 2.x reader (see the module's documentation)."""

    model: UmlModel
    xml: XmlInput
    stereotypes: StereotypeApplications
    type_refs: list
    refs: list
    annotated: list
    XID: str
    XTYPE: str
    EXTENSION: str
    _roles: dict[str, str] | None

    def _known_ids(self, ids: list[str], known: set[str]) -> set[str]:
        """R203 for ids defined twice (their lines: a slow walk, rare)."""
        if len(known) == len(ids):
            return known
        # Enterprise Architect's and MagicDraw's xmi:Extension blocks restate model ids (diagram
        # objects, EA's element table): not definitions, so not duplicates.
        return known | check_ids(
            self.model, unread.ids_outside_extensions(self.xml.root, self.XID, self.EXTENSION)
        )

    def _resolve(self, ids: list[str], known: set[str]) -> None:
        model = self.model
        known = self._known_ids(ids, known)
        self.stereotypes.resolve_references()
        # types defined where the walk does not read (EA's own types, in its extension)
        outside = self._outside(
            {o.type_ref for o in self.type_refs if o.type_ref not in model.elements} & known
        )
        roles = acordcs_roles(model)  # what makes a reference out of the file an error
        for obj in self.type_refs:
            target = model.elements.get(obj.type_ref) or outside.get(obj.type_ref)
            if target is not None:
                obj.type_name = target.name
            elif obj.type_ref not in known:
                dangling(
                    model,
                    obj.type_ref,
                    f"type of {obj.name!r}",
                    obj.line,
                    obj.qualified_name(),
                    touched(model, roles, obj),
                )
        for ident, what, line, source in self.refs:
            if ident not in known:
                dangling(
                    model,
                    ident,
                    what,
                    line,
                    source.qualified_name(),
                    touched(model, roles, source, self._joined(source)),
                )
        for assoc in model.associations:
            for ident in assoc.member_ends:
                if ident not in known:
                    dangling(
                        model,
                        ident,
                        f"member end of {assoc.name!r}",
                        assoc.line,
                        assoc.qualified_name(),
                        touched(model, roles, assoc, self._joined(assoc)),
                    )
        for ident, body in self.annotated:
            target = model.elements.get(ident)
            if target is not None:
                target.comments.append(body)
        # applications to elements the walk keeps no object for (a MagicDraw diagram, an EA
        # message): kept, on a plain element of that metaclass, instead of called dangling
        bases = self._outside(
            {a.base for a in model.applications.values() if a.base not in model.elements} & known
        )
        for app in list(model.applications.values()):
            if app.base in bases:
                model.elements[app.base] = bases[app.base]
            if app.base == app.id or app.base not in model.elements:
                del model.applications[(app.base, app.key)]
                model.diagnostics.append(
                    diagnostic(
                        "R204",
                        f"stereotype {app.key} is applied to id {app.base!r}, which no element has; "
                        "the application is ignored",
                        file=model.file,
                        line=app.line,
                        xmi_id=app.base,
                    )
                )

    def _acordcs_in(self, el: etree._Element) -> str | None:
        """What ACORD-CS reads in a skipped element ``el`` (R201): an element in it (or it) with an
        ACORD-CS stereotype applied, an application of one written inside it, or references from
        it to two elements that have one (a relation ACORD-CS would read). None when there is
        none."""
        if self._roles is None:  # once per file: thousands of skipped elements are possible
            self._roles = acordcs_roles(self.model)
        roles = self._roles
        xid = self.XID
        related: list[str] = []
        for node in el.iter(etree.Element):
            ident = node.get(xid)
            if ident in roles:
                return "holds " + described(self.model, roles, ident, node.get("name", ""))
            if (
                node is not el
                and node.tag[0] == "{"
                and any(k.startswith("base_") for k in node.attrib)
                and self.stereotypes.profile_of(node.tag) == PROFILE_NAME
            ):
                return f"holds an application of <<{local_name(node.tag)}>>"
            related += _references(node, xid, roles)
        return relates(self.model, roles, related)

    def _joined(self, source: Element) -> list[str]:
        """The ids a relation joins: a dependency's clients and suppliers, an association's (or an
        end's association's) ends and their types."""
        if isinstance(source, Dependency):
            return source.clients + source.suppliers
        assoc = source
        if isinstance(source, Property) and source.association:
            assoc = self.model.elements.get(source.association) or source
        found = [source.type_ref] if isinstance(source, Property) and source.type_ref else []
        for ident in getattr(assoc, "member_ends", ()):
            end = self.model.elements.get(ident)
            found.append(ident)
            if isinstance(end, Property) and end.type_ref:
                found.append(end.type_ref)
        return found

    def _outside(self, wanted: set[str]) -> dict[str, Element]:
        return unread.elements_by_id(self.xml.root, self.XID, self.XTYPE, wanted)


def _references(node: etree._Element, xid: str, roles: dict[str, str]) -> list[str]:
    """The ids of ACORD-CS elements ``node``'s attributes name (space-separated id lists)."""
    return [
        token
        for key, value in node.attrib.items()
        if key != xid and key != "name"
        for token in value.split()
        if token in roles
    ]
