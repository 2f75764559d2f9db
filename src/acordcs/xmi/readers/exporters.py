"""Which tool wrote a model file, and the checks that keep a reader from misreading it in silence.

Every XMI writer names itself somewhere, in one of four forms:

- XMI 2.x: ``<xmi:Documentation exporter=".." exporterVersion=".."/>`` (BOUML, Enterprise Architect,
  Visual Paradigm), the same with ``<xmi:exporter>`` / ``<xmi:exporterVersion>`` child elements
  (MagicDraw / Cameo), or that element inside an XML comment (a BOUML option);
- XMI 1.x: ``XMI.header/XMI.documentation/XMI.exporter`` and ``XMI.exporterVersion`` (Umbrello, ArgoUML,
  Visual Paradigm, MagicDraw 9, Rational Rose's Unisys exporter);
- Eclipse UML2: an ``eAnnotations`` on the model whose ``source`` is the tool (Modelio writes
  ``source="Objing"`` with an ``exporterVersion`` property); Papyrus names nothing, the Eclipse UML2
  namespace then stands for it.

:func:`review` runs after a reader: when the file holds class-like elements and the reader found no
classifier, it is an error naming the exporter (R208), never an empty model that validates clean; an
exporter this project does not know is named with an info (R209) when the file read cleanly, else
(errors, or elements skipped or references unresolved: R201, R202) a warning (R210).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from lxml import etree

from acordcs.diagnostics import Severity, diagnostic
from acordcs.xmi.uml import UmlModel


@dataclass(frozen=True)
class Exporter:
    name: str | None  # as the file states it
    version: str | None
    tool: str | None  # our key of a known tool, None when unknown
    line: int = 0

    @property
    def text(self) -> str | None:
        return " ".join(p for p in (self.name, self.version) if p) or None


# (pattern on the exporter's name, tool key, the name the docs use)
KNOWN_TOOLS: tuple[tuple[re.Pattern[str], str, str], ...] = tuple(
    (re.compile(pattern, re.IGNORECASE), key, title)
    for pattern, key, title in (
        (r"^bouml", "bouml", "BOUML"),
        (r"^acordcs$", "acordcs", "acordcs"),
        (r"enterprise architect|sparx", "enterprise-architect", "Enterprise Architect"),
        (r"magicdraw|cameo|no magic", "magicdraw", "MagicDraw / Cameo"),
        (r"modelio|objing", "modelio", "Modelio"),
        (r"visual paradigm", "visual-paradigm", "Visual Paradigm"),
        (r"papyrus|eclipse", "papyrus", "Papyrus / Eclipse UML2"),
        (r"genmymodel", "genmymodel", "GenMyModel"),
        (r"umbrello", "umbrello", "Umbrello"),
        (r"argo", "argouml", "ArgoUML"),
        (r"novosoft", "argouml", "ArgoUML (Novosoft UML library, XMI 1.0)"),
        (r"unisys|rational rose", "rose", "Rational Rose"),
    )
)

_COMMENTED = re.compile(
    r"""Documentation\b[^>]*?\bexporter\s*=\s*["']([^"']*)["']"""
    r"""(?:[^>]*?\bexporterVersion\s*=\s*["']([^"']*)["'])?"""
)


def _tool(name: str | None) -> str | None:
    if not name:
        return None
    return next((key for pattern, key, _ in KNOWN_TOOLS if pattern.search(name)), None)


def _text(el: etree._Element | None) -> str | None:
    if el is None:
        return None
    return (el.text or "").strip() or None


def _local(tag: object) -> str:
    return tag.rpartition("}")[2] if isinstance(tag, str) else ""


def detect(root: etree._Element) -> Exporter:
    """The exporter ``root``'s document states (all fields None when it states none)."""
    if root.tag == "XMI":  # XMI 1.x
        doc = root.find("XMI.header/XMI.documentation")
        if doc is not None:
            name = _text(doc.find("XMI.exporter"))
            return Exporter(
                name, _text(doc.find("XMI.exporterVersion")), _tool(name), doc.sourceline or 0
            )
        return Exporter(None, None, None)
    for child in root.iterchildren():
        local = _local(child.tag)
        if local == "Documentation":
            name = child.get("exporter") or _text(_child(child, "exporter"))
            version = child.get("exporterVersion") or _text(_child(child, "exporterVersion"))
            if name:
                return Exporter(name, version, _tool(name), child.sourceline or 0)
        elif not isinstance(child.tag, str) and child.text and "exporter" in child.text:
            found = _COMMENTED.search(child.text)
            if found:
                name = found.group(1)
                return Exporter(name, found.group(2), _tool(name), child.sourceline or 0)
    model = (
        root
        if _local(root.tag) != "XMI"
        else next(
            (c for c in root.iterchildren() if _local(c.tag) in ("Model", "Package", "Profile")),
            None,
        )
    )
    if model is not None:
        for note in model.iterchildren("eAnnotations"):
            source = note.get("source", "")
            if source and "/" not in source:  # a tool's name, not a metamodel URI
                version = next(
                    (
                        c.findtext("defaultValue") or _value(c)
                        for c in note.iterchildren("contents", "details")
                        if (c.get("name") or c.get("key") or "").lower() == "exporterversion"
                    ),
                    None,
                )
                return Exporter(source, version, _tool(source), note.sourceline or 0)
    return Exporter(None, None, None)


def _child(el: etree._Element, local: str) -> etree._Element | None:
    return next((c for c in el.iterchildren() if _local(c.tag) == local), None)


def _value(el: etree._Element) -> str | None:
    found = el.get("value")
    if found is not None:
        return found
    value = el.find("defaultValue")
    return value.get("value") if value is not None else None


# What a modeller calls a class: counted in the raw file when a reader found no classifier.
_CLASS_LIKE = frozenset(("Class", "Interface", "Enumeration", "Component", "AssociationClass"))


def _class_like(root: etree._Element) -> tuple[int, etree._Element | None, str]:
    """The class-like elements of the file, outside tool extensions (diagrams name classes too):
    their number, the first and its metaclass."""
    count, first, first_kind = 0, None, ""
    skip = None
    for el in root.iter(etree.Element):
        if skip is not None:
            if skip in el.iterancestors():
                continue
            skip = None
        local = _local(el.tag)
        if local in ("Extension", "XMI.extension", "XMI.extensions", "eAnnotations"):
            skip = el
            continue
        kind = next((v for k, v in el.items() if k.endswith("}type") or k == "xmi.type"), None)
        kind = (kind or local).rpartition(":")[2].rpartition(".")[2]
        if kind in _CLASS_LIKE and (el.get("name") is not None or len(el)):
            count += 1
            if first is None:
                first, first_kind = el, kind
    return count, first, first_kind


def _named(el: etree._Element, kind: str) -> str:
    """``Class 'Camera'``, or ``Class xmi.8 (no name)``: an empty name quoted says nothing."""
    name = el.get("name")
    if name is None:  # a name as a child element (XMI 1.0's ModelElement.name)
        name = next(
            (c.text for c in el if isinstance(c.tag, str) and c.tag.endswith(".name")), None
        )
    if name and name.strip():
        return f"{kind} {name.strip()!r}"
    ident = next((v for k, v in el.items() if k.endswith("id") and "idref" not in k), None)
    return f"{kind} {ident} (no name)" if ident else f"{kind} (no name)"


_WHAT_TO_DO = (
    "export the model as XMI 2.1 (UML 2) from the tool, or as Eclipse UML2 (.uml); see docs/uml-tools.md "
    "for the forms each tool can write"
)


def review(model: UmlModel, root: etree._Element, exporter: Exporter, dialect_rules: str) -> None:
    """Name the exporter on ``model`` and add R208/R209/R210 where the reading deserves doubt."""
    if exporter.text:
        model.exporter = exporter.text
    model.tool = exporter.tool
    named = (
        f"exporter {exporter.text!r}" if exporter.text else "an exporter that names itself nowhere"
    )
    if not model.classifiers:
        count, first, kind = _class_like(root)
        if count:
            model.diagnostics.append(
                diagnostic(
                    "R208",
                    f"the file holds {count} class-like element(s) (the first: {_named(first, kind)}, "
                    f"element {_local(first.tag)}) but none was read as a "
                    f"classifier: {named} writes a "
                    f"form the {dialect_rules} rules do not read; {_WHAT_TO_DO}",
                    file=model.file,
                    line=first.sourceline,
                )
            )
            return
    if exporter.tool is not None or (exporter.text is None and dialect_rules == "Eclipse UML2"):
        return  # Papyrus names nothing: the Eclipse namespace speaks for it
    # What the reader skipped or could not resolve counts against the reading, error or not
    clean = not any(
        d.severity is Severity.ERROR or d.code in ("R201", "R202") for d in model.diagnostics
    )
    if clean:
        model.diagnostics.append(
            diagnostic(
                "R209",
                f"{named} is not one of the tools this reader was written against; the file read "
                f"cleanly with the {dialect_rules} rules: check the counts with 'acordcs-gen inspect'",
                file=model.file,
                line=exporter.line or 1,
            )
        )
    else:
        model.diagnostics.append(
            diagnostic(
                "R210",
                f"{named} is not one of the tools this reader was written against, and reading it with "
                f"the {dialect_rules} rules found the problems reported here: they may come from the "
                f"exporter's dialect rather than the model; {_WHAT_TO_DO}",
                file=model.file,
                line=exporter.line or 1,
            )
        )
