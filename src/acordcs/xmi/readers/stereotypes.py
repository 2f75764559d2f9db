"""Stereotype applications in XMI 2.x, merged from every place a file states them.

BOUML writes each application twice: an ``xmi:Extension`` block inside the element (stereotype
names and ``Profile:Stereotype:tag`` values) and an element at the document root
(``<ACORDCS:CtxMonitor base_Class=".." frequency=".."/>``); Eclipse UML2 writes only the latter,
with multi-valued tags as child elements. One application per (element, stereotype) results; a tag
that differs between the two places is R205 (see ``shared/reference/bouml-xmi.md``).
"""

from __future__ import annotations

import re

from lxml import etree

from acordcs.diagnostics import diagnostic
from acordcs.xmi.uml import Element, StereotypeApplication, UmlModel

# Where a profile's namespace URI names the profile: BOUML and Eclipse (http:///schemas/P/..),
# Enterprise Architect (http://www.sparxsystems.com/profiles/P/1.0), MagicDraw (.../schemas/P.xmi).
_PROFILE_NS = re.compile(
    r"^http:///schemas/([^/]+)/"
    r"|^https?://www\.sparxsystems\.com/profiles/([^/]+)/"
    r"|^https?://www\.magicdraw\.com/schemas/([^/]+?)\.xmi$"
)


def local_name(tag: str) -> str:
    return tag.rpartition("}")[2]


class StereotypeApplications:
    """Collects the applications of one model into ``model.applications``."""

    def __init__(self, model: UmlModel, xmi_id: str) -> None:
        self.model = model
        self.XID = xmi_id
        self.XIDREF = xmi_id[:-2] + "idref"
        self._profiles: dict[str, str | None] = {}  # profile named by a namespace URI, if any
        self._references: list[tuple[str, str, int]] = []  # (stereotype id, base id, line)

    def application(
        self, profile: str | None, name: str, base: str, line: int
    ) -> StereotypeApplication:
        key = (base, f"{profile}:{name}" if profile else name)
        app = self.model.applications.get(key)
        if app is None:
            app = StereotypeApplication(profile=profile, name=name, base=base, line=line)
            self.model.applications[key] = app
        return app

    def set_tag(
        self, app: StereotypeApplication, tag: str, value: str, line: int, place: str
    ) -> None:
        old = app.tags.get(tag)
        if old is not None and old != value:
            if place not in app.places:  # BOUML's other place
                says = (
                    f"is {old!r} in one place and {value!r} in the other; using {old!r}: re-export"
                )
            else:  # one place twice: two applications of one stereotype to one element
                says = (
                    f"is stated twice, {old!r} then {value!r}; using {old!r}: apply the stereotype "
                    "once"
                )
            base = self.model.elements.get(app.base)
            self.model.diagnostics.append(
                diagnostic(
                    "R205",
                    f"tag {tag!r} of {app.key} {says} the model",
                    file=self.model.file,
                    line=line,
                    element=base.qualified_name() if base is not None else None,
                    xmi_id=app.base,
                )
            )
            return
        app.tags[tag] = value
        app.tag_lines.setdefault(tag, line)

    def extension(self, el: etree._Element, owner: Element) -> None:
        """A BOUML ``xmi:Extension`` block of ``owner``: its stereotypes and tagged values."""
        extender = el.get("extender", "Bouml")
        if extender == "Visual Paradigm":
            self._visual_paradigm(el, owner)
        if extender != "Bouml":
            return
        # BOUML marks its profile definitions with their own metaclass keyword (a Stereotype is
        # <<stereotype>>, a Profile <<profile>>): keywords, not stereotype applications.
        keyword = owner.kind.lower()
        line = el.sourceline or owner.line
        for s in el.iterchildren("stereotype"):
            name = s.get("name", "")
            if name == keyword:
                continue
            profile, _, stereo = name.rpartition(":")
            self.application(profile or None, stereo, owner.id, line).places.add("extension")
        found: dict[str, StereotypeApplication] = {}  # a block's tags come by stereotype
        for tv in el.iterchildren("taggedValue"):
            tag = tv.get("tag", "")
            if tag.startswith("gxmi "):
                continue  # BOUML's own export options
            value = tv.get("value", "")
            parts = tag.split(":")
            if len(parts) == 3:
                tv_line = tv.sourceline or 0
                key = tag[: -len(parts[2]) - 1]
                app = found.get(key)
                if app is None:
                    app = found[key] = self.application(
                        parts[0], parts[1], owner.id, tv_line or owner.line
                    )
                self.set_tag(app, parts[2], value, tv_line, "extension")
            else:
                owner.tagged_values[tag] = value

    def _visual_paradigm(self, el: etree._Element, owner: Element) -> None:
        """Visual Paradigm's XMI 2.1 names the stereotypes of an element in its extension block,
        ``<appliedStereotype xmi:value="Class_CtxMonitor_id"/>``, the id of a ``uml:Stereotype`` of
        the model; resolved by :meth:`resolve_references` once every element is read."""
        for applied in el.iterchildren("appliedStereotype"):
            ref = next((v for k, v in applied.items() if k.endswith("value")), None)
            if ref:
                self._references.append((ref, owner.id, applied.sourceline or owner.line))

    def resolve_references(self) -> None:
        """Applications stated by reference to a stereotype (Visual Paradigm): the stereotype's
        profile is the ``uml:Profile`` that owns it, none for a stereotype outside a profile."""
        for ref, base, line in self._references:
            stereo = self.model.elements.get(ref)
            if stereo is None or stereo.kind != "Stereotype":
                continue
            owner = stereo.owner
            while owner is not None and owner.kind not in ("Profile", "Model"):
                owner = owner.owner
            profile = owner.name if owner is not None and owner.kind == "Profile" else None
            self.application(profile, stereo.name, base, line).places.add("extension")

    def profile_of(self, tag: str) -> str | None:
        """The profile a stereotype application's namespace names (``{http:///schemas/P/1}St``:
        P), None when it names none."""
        ns = tag[1:].rpartition("}")[0] if tag[0] == "{" else ""
        if ns not in self._profiles:
            match = _PROFILE_NS.match(ns)
            self._profiles[ns] = next((g for g in match.groups() if g), None) if match else None
        return self._profiles[ns]

    def root_application(self, el: etree._Element) -> None:
        """A stereotype application written at the document root (``Profile:Stereotype base_X=..``)."""
        items = el.items()
        base = next((value for key, value in items if key.startswith("base_")), None)
        if base is None:
            return
        tag = el.tag
        line = el.sourceline or 0
        if tag[0] != "{" and ":" in tag:  # a recovered element whose prefix was never declared
            self.model.diagnostics.append(
                diagnostic(
                    "R201",
                    f"element {tag} uses an undeclared namespace prefix; the stereotype application "
                    "is skipped: declare the prefix on the root element",
                    file=self.model.file,
                    line=el.sourceline,
                )
            )
            return
        name = tag[1:].rpartition("}")[2] if tag[0] == "{" else tag
        # The namespace names the profile; a prefix is the writer's choice (xmlns:acs= works too).
        profile = self.profile_of(tag) or el.prefix
        app = self.application(profile, name, base, line)
        app.id = el.get(self.XID)
        app.line = line or app.line
        for key, value in items:
            if key.startswith(("base_", "{", "__EA")):  # EA's __EAStereoName: its display name
                continue
            self.set_tag(app, key, value, line, "root")
        for child in el:  # Eclipse writes multi-valued and reference tags as child elements
            if isinstance(child.tag, str):
                tag = local_name(child.tag)
                value = child.text
                if value is None:  # a reference: MagicDraw writes xmi:idref, Eclipse href
                    value = child.get(self.XIDREF) or child.get("href", "")
                old = app.tags.get(tag)
                app.tags[tag] = value if old is None else f"{old}\n{value}"
                app.tag_lines.setdefault(tag, child.sourceline or 0)
        app.places.add("root")
