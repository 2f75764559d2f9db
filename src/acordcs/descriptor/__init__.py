"""The application descriptor: one source of truth between a model and what is built from it.

``describe(arch)`` reads an interpreted model (:mod:`acordcs.model.architecture`) into frozen plain
data (:mod:`.model`); ``to_xml`` / ``from_xml`` (:mod:`.xml`) write and read it as the XML
deployment descriptor, validated against ``acordcs-descriptor.xsd``; the code generator's
stylesheets read that document, and ``assemble`` builds running containers from the data::

    from acordcs.descriptor import describe, to_xml
    from acordcs.model.reading import read_model

    app = describe(read_model("samples/weblab/weblab.xmi").architecture)
    data = to_xml(app)
"""

from acordcs.descriptor.describe import describe, typed_default, value_kind
from acordcs.descriptor.model import (
    Application,
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
)
from acordcs.descriptor.xml import NAMESPACE, from_xml, schema, to_xml

__all__ = [
    "NAMESPACE",
    "Application",
    "Component",
    "Connection",
    "Container",
    "DescriptorError",
    "End",
    "Endpoint",
    "Monitor",
    "Operation",
    "Parameter",
    "Policy",
    "PolicySet",
    "Port",
    "Property",
    "Ref",
    "Rule",
    "Term",
    "Variable",
    "describe",
    "from_xml",
    "schema",
    "to_xml",
    "typed_default",
    "value_kind",
]
