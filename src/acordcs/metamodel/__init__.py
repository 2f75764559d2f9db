"""The ACORD-CS metamodel, loaded by pyecore from ``acordcs.ecore`` (its only declaration).

pyecore is imported on first use, not at import time: ``acordcs-gen validate`` reads the profile and the
rule grammar from this package and must not pay pyecore's start-up on every run.
"""

from __future__ import annotations

import os
from functools import cache
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pyecore.ecore import EClass, EPackage

ECORE_FILE = "acordcs.ecore"
NS_URI = "http://acordcs.org/acordcs/1.0"
PROFILE_SOURCE = "http://acordcs.org/profile"


def ecore_path() -> str:
    """Filesystem path of the shipped ``acordcs.ecore``."""
    return os.path.join(os.path.dirname(__file__), ECORE_FILE)


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


def save_model(root, path: str) -> None:
    """Write an ACORD-CS model (an ``Application``) as an XMI instance file EMF can load.

    Default values are written too: pyecore otherwise drops a value equal to the default, and an
    unsettable feature set to it (a frequency of 0.0) would come back unset.
    """
    from pyecore.resources import URI, ResourceSet
    from pyecore.resources.xmi import XMIOptions

    rset = ResourceSet()
    rset.metamodel_registry[NS_URI] = load()
    resource = rset.create_resource(URI(str(path)))
    resource.append(root)
    resource.save(options={XMIOptions.SERIALIZE_DEFAULT_VALUES: True})


def load_model(path: str):
    """Read an ACORD-CS model instance file written by :func:`save_model` (or by EMF)."""
    from pyecore.resources import URI, ResourceSet

    rset = ResourceSet()
    rset.metamodel_registry[NS_URI] = load()
    return rset.get_resource(URI(str(path))).contents[0]
