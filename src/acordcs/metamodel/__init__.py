"""The ACORD-CS metamodel, loaded by pyecore from ``acordcs.ecore`` (its only declaration).

pyecore is imported on first use, not at import time: ``acordcs-gen validate`` reads the profile and the
rule grammar from this package and must not pay pyecore's start-up on every run.
"""

from __future__ import annotations

import io
from functools import cache
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pyecore.ecore import EClass, EPackage

from acordcs.vocabularies import ECORE_PATH

ECORE_FILE = "acordcs.ecore"
NS_URI = "http://acordcs.org/acordcs/1.0"
PROFILE_SOURCE = "http://acordcs.org/profile"


def ecore_path() -> str:
    """Filesystem path of the shipped ``acordcs.ecore`` (its enumerations without pyecore:
    :mod:`acordcs.vocabularies`)."""
    return ECORE_PATH


@cache
def load() -> EPackage:
    """The metamodel's root EPackage (loaded once per process)."""
    from pyecore.resources import URI, ResourceSet

    rset = ResourceSet()
    resource = rset.get_resource(URI(ecore_path()))
    return resource.contents[0]


def eclass(name: str) -> EClass:
    """An EClass of the metamodel by name; KeyError names the known ones."""
    from pyecore.ecore import EClass

    found = load().getEClassifier(name)
    if not isinstance(found, EClass):
        known = ", ".join(c.name for c in load().eClassifiers if isinstance(c, EClass))
        raise KeyError(f"no EClass {name!r} in the ACORD-CS metamodel (known: {known})")
    return found


def create(class_name: str, /, **features: object):
    """A new instance of EClass ``class_name`` with the given features set (None values skipped)."""
    obj = eclass(class_name)()
    for key, value in features.items():
        if value is None:
            continue
        if isinstance(value, list):
            getattr(obj, key).extend(value)
        else:
            setattr(obj, key, value)
    return obj


def instance_bytes(root, *, schema_location: str | None = None) -> bytes:
    """An ACORD-CS model (an ``Application``) as the bytes of an XMI instance file EMF loads.

    Default values are written too: pyecore otherwise drops a value equal to the default, and an
    unsettable feature set to it (a frequency of 0.0) would come back unset. ``schema_location``:
    where the metamodel file is, relative to the instance file; it goes into ``xsi:schemaLocation``
    (paired with :data:`NS_URI`), which EMF follows to load the metamodel when it has none
    registered under that namespace.
    """
    from pyecore.resources import URI, ResourceSet
    from pyecore.resources.xmi import XMIOptions

    buffer = io.BytesIO()

    class InMemory(URI):  # where pyecore writes: a file is then written whole, or not at all
        def create_outstream(self) -> io.BytesIO:
            return buffer

    rset = ResourceSet()
    rset.metamodel_registry[NS_URI] = load()
    resource = rset.create_resource(URI("model.xmi"))
    resource.append(root)
    resource.save(output=InMemory("model.xmi"), options={XMIOptions.SERIALIZE_DEFAULT_VALUES: True})
    data = buffer.getvalue()
    if schema_location is None:
        return data
    from lxml import etree

    tree = etree.fromstring(data, etree.XMLParser(resolve_entities=False, no_network=True))
    tree.set(f"{{{_XSI}}}schemaLocation", f"{NS_URI} {schema_location}")
    return etree.tostring(tree, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def save_model(root, path: str) -> None:
    """Write an ACORD-CS model (an ``Application``) as an XMI instance file EMF can load."""
    with open(path, "wb") as handle:
        handle.write(instance_bytes(root))


_XSI = "http://www.w3.org/2001/XMLSchema-instance"
