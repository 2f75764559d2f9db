"""The application descriptor: one source of truth between a model and what is built from it.

A leaf package: frozen plain data (:mod:`.application`, whose annotated fields are the one declaration
of the XML form: :mod:`.xml_form`), and ``to_xml`` / ``from_xml`` (:mod:`.xml`) writing and
reading it as the XML deployment descriptor, validated against ``acordcs-descriptor.xsd`` (which
:mod:`.xsd` writes from the declaration). It imports nothing of the toolchain: a generated
application reads its descriptor with it. The toolchain makes a descriptor from a model with
:func:`acordcs.generator.describe.describe`; the code generator's stylesheets read the document, and
:func:`acordcs.runtime.assembly.assemble` builds running containers from the data::

    from acordcs.descriptor import to_xml
    from acordcs.generator.describe import describe
    from acordcs.model.reading import read_model

    app = describe(read_model("samples/weblab/weblab.xmi").architecture)
    data = to_xml(app)
"""

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
)
from acordcs.descriptor.xml import NAMESPACE, from_xml, schema, to_xml
from acordcs.typed_values import parse_real, typed_default, value_kind

__all__ = [
    "NAMESPACE",
    "Application",
    "Bound",
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
    "from_xml",
    "parse_real",
    "schema",
    "to_xml",
    "typed_default",
    "value_kind",
]
