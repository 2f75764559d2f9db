"""Readers from the XMI that real tools write to the neutral UML view (:mod:`acordcs.xmi.uml`)."""

from __future__ import annotations

from acordcs.diagnostics import diagnostic
from acordcs.xmi.source import XmlInput, read_xml
from acordcs.xmi.uml import UmlModel


def read_uml(path: str) -> UmlModel:
    """Read any supported export (XMI 2.x of BOUML, Enterprise Architect, MagicDraw / Cameo, Visual
    Paradigm; Eclipse UML2 of Papyrus and Modelio; XMI 1.x of UML 1.3/1.4 tools). Never raises for bad
    input; see ``docs/uml-tools.md``."""
    from acordcs.xmi.readers import exporters, xmi2, xmi10, xmi12

    xml = read_xml(path)
    if xml.root is None:
        return UmlModel(file=path, dialect="unreadable", diagnostics=xml.diagnostics)
    root = xml.root
    exporter = exporters.detect(root)
    if xmi12.accepts(root):
        if xmi10.long_names(root):
            xmi10.normalise(root)  # XMI 1.0's Foundation.Core.Class: into XMI 1.1's form
        model = xmi12.read(xml, exporter)
        rules = "XMI 1.x (UML 1.3/1.4)"
    elif xmi2.accepts(root):
        model = xmi2.read(xml, exporter.tool)
        rules = "Eclipse UML2" if model.dialect == "eclipse-uml2" else "XMI 2.x (UML 2)"
        if model.dialect == "bouml-xmi2" and exporter.tool not in (None, "bouml", "acordcs"):
            model.dialect = "omg-xmi2"  # the same rules; not BOUML's file
    else:
        return _not_uml(xml, exporter)
    exporters.review(model, root, exporter, rules)
    model.diagnostics[:0] = xml.diagnostics
    return model


def _not_uml(xml: XmlInput, exporter) -> UmlModel:
    tag = xml.root.tag if isinstance(xml.root.tag, str) else "?"
    by = f" (written by {exporter.text})" if exporter.text else ""
    msg = (
        f"root element {tag}{by} is not XMI or UML this reader knows: export the model as XMI 2.1 "
        "(UML 2) or Eclipse UML2 (.uml); docs/uml-tools.md says how for each tool"
    )
    diags = [*xml.diagnostics, diagnostic("X109", msg, file=xml.path, line=xml.root.sourceline)]
    return UmlModel(file=xml.path, dialect="unreadable", diagnostics=diags, exporter=exporter.text)
