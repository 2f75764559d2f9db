"""Enterprise Architect's XMI 1.1: its profile stereotypes and its own tagged values.

EA's XMI 1.1 export has no UML 2 profile applications. It names an element's stereotypes, profile
included, in one tagged value, ``$ea_xref_property``::

    $XREFPROP=$XID={..}$XID;$NAM=Stereotypes$NAM;...$DES=@STEREO;Name=CtxMonitor;GUID={..};
    FQName=ACORDCS::CtxMonitor;@ENDSTEREO;$DES;...

(``FQName`` is ``Profile::Stereotype``; a stereotype of no profile has none), and writes the element's
properties as tagged values too (``ea_guid``, ``date_created``, ``gentype``, ...): those are EA's, not
the modeller's tags, and would read as unknown tags of a stereotype.
"""

from __future__ import annotations

import re

XREF_TAG = "$ea_xref_property"
_STEREO = re.compile(
    r"@STEREO;Name=([^;@]*);(?:[^@]*?FQName=([^;@]*?)::([^;@]*);)?[^@]*@ENDSTEREO;"
)

# The element properties EA 6 to 16 writes as tagged values in XMI 1.1 (besides ea_* and $ea_*).
_OWN_TAGS = frozenset(
    """stereotype isSpecification package package_name date_created date_modified gentype tagged phase author
    complexity status version style styleex product_name tpos isActive batchsave batchload
    documentation lastloaddate lastsavedate scope sourcestyle deststyle src_visibility
    dst_visibility src_aggregation dst_aggregation src_containment dst_containment
    src_isNavigable dst_isNavigable virtualInheritance direction type owner alias""".split()
)


def stereotypes(xref: str) -> list[tuple[str | None, str]]:
    """(profile or None, stereotype) for each ``@STEREO`` block of an ``$ea_xref_property`` value."""
    found = []
    for name, profile, fq_name in _STEREO.findall(xref):
        found.append((profile or None, fq_name or name) if profile else (None, name))
    return found


def own_tag(tag: str) -> bool:
    """Whether ``tag`` is one of EA's element properties written as a tagged value."""
    return tag.startswith(("ea_", "$ea_")) or tag in _OWN_TAGS
