"""Target ``config``: the XML deployment descriptor and its schema, by an XSLT 3.0 stylesheet.

Writes ``<model>.descriptor.xml`` (the descriptor :func:`acordcs.descriptor.to_xml` makes, with a
header comment naming the model and the model file) and ``acordcs-descriptor.xsd`` (a copy of the
shipped schema, same header). ``config.xsl`` does it: a stylesheet so that the XSLT path of the
generator is a real, tested one (the descriptor is XML already; the transform is a copy).
"""

from __future__ import annotations

from importlib import resources

from acordcs.generator.target import xslt_target

TARGET = xslt_target(
    "config",
    resources.files("acordcs.transforms") / "config.xsl",
    description="the XML deployment descriptor <model>.descriptor.xml and its schema (XSLT 3.0)",
)
