"""Readers from the XMI that real tools write to the neutral UML view (:mod:`acordcs.xmi.uml`)."""

from __future__ import annotations

from acordcs.diagnostics import diagnostic
from acordcs.xmi.source import XmlInput, read_xml
from acordcs.xmi.uml import UmlModel


def read_uml(path: str) -> UmlModel:
    """Read any supported export (BOUML XMI 2.x or 1.2, Eclipse UML2 / Papyrus). Never raises for bad input."""
    from acordcs.xmi.readers import xmi2, xmi12

    xml = read_xml(path)
    if xml.root is None:
        return UmlModel(file=path, dialect="unreadable", diagnostics=xml.diagnostics)
    root = xml.root
    if xmi12.accepts(root):
        model = xmi12.read(xml)
    elif xmi2.accepts(root):
        model = xmi2.read(xml)
    else:
        return _not_uml(xml)
    model.diagnostics[:0] = xml.diagnostics
    return model


def _not_uml(xml: XmlInput) -> UmlModel:
    tag = xml.root.tag if isinstance(xml.root.tag, str) else "?"
    msg = (
        f"root element {tag} is not XMI or UML: export the model from BOUML (XMI 2.1, 'generate "
        "extensions' on) or save it from Papyrus as .uml"
    )
    diags = [*xml.diagnostics, diagnostic("X109", msg, file=xml.path, line=xml.root.sourceline)]
    return UmlModel(file=xml.path, dialect="unreadable", diagnostics=diags)
