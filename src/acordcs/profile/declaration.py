"""The ACORDCS profile as data, read from the annotations of ``acordcs.ecore``.

The metamodel is the one declaration: an EClass annotated (source ``http://acordcs.org/profile``) with
``stereotype`` and ``metaclasses`` is a stereotype; a feature of it annotated with ``tag`` is a tagged
value whose type, default and permitted values come from the feature (an EEnum gives the permitted
values) unless ``syntax`` names a text syntax, in which case the tag is a string in that syntax.
``prefix="true"`` means every tag whose name starts with the tag's name belongs to it (``Rule``,
``RuleSlowDown``, ...), as the paper puts the rule name in the tag name.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from acordcs import metamodel, vocabularies

PROFILE_NAME = "ACORDCS"
PROFILE_URI = "http:///schemas/ACORDCS/1"

_TYPE_NAMES = {"EString": "String", "EDouble": "Real", "EInt": "Integer", "EBoolean": "Boolean"}


@dataclass(frozen=True)
class Tag:
    """A tagged value of a stereotype."""

    name: str
    type: str  # String, Real, Integer, Boolean, or an enumeration name
    default: str | None
    values: tuple[str, ...]  # permitted values; empty when not finite
    feature: str  # the metamodel feature it sets
    syntax: str | None = None  # rules | terms: a string in that text syntax
    prefix: bool = False
    doc: str = ""

    def matches(self, tag_name: str) -> bool:
        return tag_name == self.name or (self.prefix and tag_name.startswith(self.name))


@dataclass(frozen=True)
class Stereotype:
    """A stereotype of the profile: same name as its metamodel EClass."""

    name: str
    metaclasses: tuple[str, ...]
    tags: tuple[Tag, ...]
    doc: str = ""

    def tag(self, tag_name: str) -> Tag | None:
        """The tag declaration a tag of this name belongs to (exact name first, then prefixes)."""
        for t in self.tags:
            if t.name == tag_name:
                return t
        for t in self.tags:
            if t.matches(tag_name):
                return t
        return None


_GENMODEL = "http://www.eclipse.org/emf/2002/GenModel"


def _details(element, source: str) -> dict[str, str]:
    for ann in element.iterfind("eAnnotations"):
        if ann.get("source") == source:
            return {d.get("key"): d.get("value", "") for d in ann.iterfind("details")}
    return {}


def _type_name(etype: str) -> str:
    """``ecore:EDataType http://...Ecore#//EDouble`` or ``#//PortKind`` -> ``EDouble`` / ``PortKind``."""
    return etype.rpartition("//")[2]


def _tag(feature, enums: dict[str, tuple[str, ...]]) -> Tag | None:
    details = _details(feature, metamodel.PROFILE_SOURCE)
    if "tag" not in details:
        return None
    syntax = details.get("syntax")
    etype = _type_name(feature.get("eType", ""))
    values: tuple[str, ...] = ()
    if syntax:
        type_name = "String"
    elif etype in enums:
        type_name, values = etype, enums[etype]
    else:
        type_name = _TYPE_NAMES.get(etype, etype)
    return Tag(
        name=details["tag"],
        type=type_name,
        default=feature.get("defaultValueLiteral"),
        values=values,
        feature=feature.get("name"),
        syntax=syntax,
        prefix=details.get("prefix") == "true",
        doc=_details(feature, _GENMODEL).get("documentation", ""),
    )


@cache
def profile() -> tuple[Stereotype, ...]:
    """Every stereotype of the profile, in metamodel order.

    Read straight from ``acordcs.ecore`` with lxml (:mod:`acordcs.vocabularies`) rather than through
    pyecore: the validator needs the profile on every run and pyecore's import alone would cost more
    than validating a small model.
    """
    classifiers = vocabularies.ecore_root().findall("eClassifiers")
    enums = vocabularies.enumerations()
    by_name = {c.get("name"): c for c in classifiers}

    def features(eclass) -> list:
        inherited = []
        for sup in (eclass.get("eSuperTypes") or "").split():
            inherited += features(by_name[_type_name(sup)])
        return inherited + eclass.findall("eStructuralFeatures")

    out = []
    for classifier in classifiers:
        details = _details(classifier, metamodel.PROFILE_SOURCE)
        if "stereotype" not in details:
            continue
        tags = tuple(t for f in features(classifier) if (t := _tag(f, enums)))
        out.append(
            Stereotype(
                name=details["stereotype"],
                metaclasses=tuple(details.get("metaclasses", "Class").split()),
                tags=tags,
                doc=_details(classifier, _GENMODEL).get("documentation", ""),
            )
        )
    return tuple(out)


def stereotype(name: str) -> Stereotype | None:
    """The stereotype named ``name`` (without the ``ACORDCS:`` prefix), or None."""
    for s in profile():
        if s.name == name:
            return s
    return None
