"""The metamodel's vocabularies: the literals of the enumerations (EEnums) of ``acordcs.ecore``.

``acordcs.ecore`` declares them once (port kinds and roles, engines, semantics, triggers,
implementation languages, connectors, membership shapes, parameter directions, acquisition kinds);
the runtime, the profile, the metamodel package and the descriptor's schema take them from here.
This module is a leaf: it reads the shipped file by its path beside this module with the standard
library's parser, without importing :mod:`acordcs.metamodel` (which needs pyecore) nor lxml (which
the runtime loads only when it reads XML), so that a generated application, which imports the
runtime and never the toolchain, checks what the metamodel declares.
"""

from __future__ import annotations

import os
from functools import cache
from xml.etree import ElementTree

ECORE_PATH = os.path.join(os.path.dirname(__file__), "metamodel", "acordcs.ecore")
"""The shipped metamodel file."""

_XSI_TYPE = "{http://www.w3.org/2001/XMLSchema-instance}type"


@cache
def ecore_root() -> ElementTree.Element:
    """The root ``EPackage`` element of ``acordcs.ecore``, parsed once per process (our own file:
    expat, which fetches nothing)."""
    return ElementTree.parse(ECORE_PATH).getroot()


@cache
def enumerations() -> dict[str, tuple[str, ...]]:
    """Every EEnum of the metamodel by name: its literals, in declaration order (the first is
    EMF's default value of an attribute of that type)."""
    return {
        c.get("name"): tuple(lit.get("name") for lit in c.iterfind("eLiterals"))
        for c in ecore_root().iterfind("eClassifiers")
        if c.get(_XSI_TYPE) == "ecore:EEnum"
    }


def literals(enum: str) -> tuple[str, ...]:
    """The literals of EEnum ``enum``; ``KeyError`` names the EEnums there are."""
    found = enumerations().get(enum)
    if found is None:
        raise KeyError(
            f"no EEnum {enum!r} in acordcs.ecore (there are: {', '.join(sorted(enumerations()))})"
        )
    return found


PORT_KINDS = literals("PortKind")
PORT_ROLES = literals("PortRole")
ENGINES = literals("EngineKind")
FUZZY_ENGINE, CLIPS_ENGINE = ENGINES
"""The metamodel's two engine kinds by name, for code that treats one apart (a literal added to or
renamed in ``EngineKind`` fails here, at import, not in some comparison that no longer matches)."""
SEMANTICS = literals("FuzzySemantics")
TRIGGERS = literals("PolicyTrigger")
LANGUAGES = literals("ImplementationLanguage")
CONNECTORS = literals("ConnectorKind")
SHAPES = literals("MembershipShape")
DIRECTIONS = literals("ParameterDirection")
IN, OUT, INOUT, RETURN = DIRECTIONS
ARGUMENT_DIRECTIONS = (IN, INOUT)
"""The parameters a caller passes, in the model's order: the operation's Python arguments."""
RESULT_DIRECTIONS = (OUT, INOUT)
"""The parameters whose final values come back, after the return value, in the model's order: an
operation with any returns the tuple (return value, their values...). One mapping, read by the
runtime (:mod:`acordcs.runtime.operations`) and given to the ``python`` target's stylesheet."""
ACQUISITIONS = literals("MonitorAcquisition")
