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

from pyecore.ecore import EAttribute, EClass, EEnum

from acordcs import metamodel

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


def _doc(element) -> str:
    ann = element.getEAnnotation("http://www.eclipse.org/emf/2002/GenModel")
    return ann.details.get("documentation", "") if ann else ""


def _tag(feature) -> Tag | None:
    ann = feature.getEAnnotation(metamodel.PROFILE_SOURCE)
    if ann is None or "tag" not in ann.details:
        return None
    syntax = ann.details.get("syntax")
    etype = feature.eType
    values: tuple[str, ...] = ()
    if syntax:
        type_name = "String"
    elif isinstance(etype, EEnum):
        type_name = etype.name
        values = tuple(lit.name for lit in etype.eLiterals)
    else:
        type_name = _TYPE_NAMES.get(etype.name, etype.name)
    default = None
    if isinstance(feature, EAttribute) and feature.defaultValueLiteral is not None:
        default = feature.defaultValueLiteral
    return Tag(
        name=ann.details["tag"],
        type=type_name,
        default=default,
        values=values,
        feature=feature.name,
        syntax=syntax,
        prefix=ann.details.get("prefix") == "true",
        doc=_doc(feature),
    )


@cache
def profile() -> tuple[Stereotype, ...]:
    """Every stereotype of the profile, in metamodel order."""
    out = []
    for classifier in metamodel.load().eClassifiers:
        if not isinstance(classifier, EClass):
            continue
        ann = classifier.getEAnnotation(metamodel.PROFILE_SOURCE)
        if ann is None or "stereotype" not in ann.details:
            continue
        tags = tuple(t for f in classifier.eAllStructuralFeatures() if (t := _tag(f)))
        out.append(
            Stereotype(
                name=ann.details["stereotype"],
                metaclasses=tuple(ann.details.get("metaclasses", "Class").split()),
                tags=tags,
                doc=_doc(classifier),
            )
        )
    return tuple(out)


def stereotype(name: str) -> Stereotype | None:
    """The stereotype named ``name`` (without the ``ACORDCS:`` prefix), or None."""
    for s in profile():
        if s.name == name:
            return s
    return None
