"""What the XMI readers share: primitive type names and id bookkeeping (UML metaclass names:
:mod:`acordcs.xmi.readers.skipped`)."""

from __future__ import annotations

from collections import defaultdict

from acordcs.diagnostics import diagnostic
from acordcs.xmi.uml import UmlModel

# The fragment of an OMG / Eclipse primitive-type href -> the type name a modeller writes. Never fetched.
PRIMITIVE_TYPES = {
    "string": "string",
    "integer": "int",
    "boolean": "bool",
    "real": "double",
    "unlimitednatural": "long",  # BOUML writes its `long` as UnlimitedNatural
    "estring": "string",
    "eint": "int",
    "eboolean": "bool",
    "edouble": "double",
    "efloat": "float",
    "elong": "long",
    "double": "double",
    "int": "int",
    "float": "float",
    "long": "long",
    "char": "char",
    "byte": "byte",
    "short": "short",
    "boolean_": "bool",
}


def primitive_from_href(href: str) -> str:
    fragment = href.rpartition("#")[2]
    return PRIMITIVE_TYPES.get(fragment.lower(), fragment)


def check_ids(model: UmlModel, ids: list[tuple[str, int]]) -> set[str]:
    """Report ids defined twice (R203); return the set of all ids."""
    known = {ident for ident, _ in ids}
    if len(known) == len(ids):  # the usual case: no line bookkeeping
        return known
    lines: dict[str, list[int]] = defaultdict(list)
    for ident, line in ids:
        lines[ident].append(line)
    for ident, where in lines.items():
        if len(where) > 1:
            where.sort()
            model.diagnostics.append(
                diagnostic(
                    "R203",
                    f"id {ident!r} is defined {len(where)} times (lines "
                    f"{', '.join(map(str, where[:10]))}{', ...' if len(where) > 10 else ''}); "
                    "ids must be unique: re-export the model",
                    file=model.file,
                    line=where[0],
                    xmi_id=ident,
                )
            )
    return set(lines)


def dangling(model: UmlModel, ident: str, what: str, line: int, element: str | None) -> None:
    model.diagnostics.append(
        diagnostic(
            "R202",
            f"{what} refers to id {ident!r}, which no element has; re-export the model or restore the element",
            file=model.file,
            line=line,
            element=element,
            xmi_id=ident,
        )
    )
