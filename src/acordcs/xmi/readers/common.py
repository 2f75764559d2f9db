"""What the XMI readers share: primitive type names, id bookkeeping (UML metaclass names:
:mod:`acordcs.xmi.readers.skipped`), and which elements ACORD-CS reads, which decides whether what
a reader could not read is an error or a warning (R201, R202).

The view itself is not ACORD-CS specific; only the severity of those two findings is: a reference
out of the file, or an element of an unknown type, costs ACORD-CS nothing unless it holds, or is
made by, an element with an ACORD-CS stereotype (one of the ACORDCS profile, or a free stereotype
of the same name, which :mod:`acordcs.model.architecture` reads as one).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable

from acordcs.diagnostics import Severity, diagnostic
from acordcs.xmi.uml import Element, UmlModel

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


def acordcs_roles(model: UmlModel) -> dict[str, str]:
    """Element id -> the ACORD-CS stereotype applied to it, for every element that has one."""
    from acordcs.profile import PROFILE_NAME, stereotype  # the profile's names, read once

    found: dict[str, str] = {}
    for app in model.applications.values():
        if app.profile == PROFILE_NAME or (app.profile is None and stereotype(app.name)):
            found.setdefault(app.base, app.name)
    return found


def described(model: UmlModel, roles: dict[str, str], ident: str, name: str = "") -> str:
    """``<<CtxComponent>> 'Heater'``: the element ``ident`` by its ACORD-CS stereotype and name."""
    element = model.elements.get(ident)
    name = (element.name if element is not None else "") or name
    return f"<<{roles[ident]}>> {name!r}" if name else f"<<{roles[ident]}>> {ident}"


def relates(model: UmlModel, roles: dict[str, str], related: Iterable[str]) -> str | None:
    """``relates <<A>> 'a' and <<B>> 'b'`` when ``related`` (the ids an element of an unknown type
    names) holds two elements with ACORD-CS stereotypes: were it a relation, ACORD-CS would read it
    (a deployment, a port's connection, ...). None otherwise: a reference to one such element alone
    (a constraint on it, say) is nothing ACORD-CS reads."""
    distinct = list(dict.fromkeys(related))
    if len(distinct) < 2:
        return None
    first, second = (described(model, roles, ident) for ident in distinct[:2])
    return f"relates {first} and {second}"


def touched(
    model: UmlModel, roles: dict[str, str], source: Element | None, others: Iterable[str] = ()
) -> str | None:
    """The ACORD-CS element a reference of ``source`` belongs to (``source`` or an owner of it: an
    attribute's class, a parameter's operation's class), else the first of ``others`` (the ids a
    relation joins) that is one; None when it touches none."""
    node = source
    while node is not None:
        if node.id in roles:
            return described(model, roles, node.id)
        node = node.owner
    for ident in others:
        if ident in roles:
            return described(model, roles, ident)
    return None


def dangling(
    model: UmlModel,
    ident: str,
    what: str,
    line: int,
    element: str | None,
    touches: str | None = None,
) -> None:
    """R202: ``what`` refers to ``ident``, which is not in the file. An error when it is a reference
    of (or to, for a relation) the ACORD-CS element ``touches``: what ACORD-CS reads is then
    incomplete; a warning otherwise: an element of another file (a package exported alone names
    what it left out) or one deleted, and ACORD-CS reads nothing through it."""
    if touches:
        message = (
            f"{what} refers to id {ident!r}, which no element of the file has, and {touches} needs "
            "it (ACORD-CS reads this reference): restore the element, or export the whole model"
        )
        severity = Severity.ERROR
    else:
        message = (
            f"{what} refers to id {ident!r}, which is not in this file (an element of another file, "
            "or one deleted); it touches no ACORD-CS element, so the reference is only left out: "
            "export the whole model, or restore the element, if it matters"
        )
        severity = Severity.WARNING
    model.diagnostics.append(
        diagnostic(
            "R202",
            message,
            file=model.file,
            line=line,
            element=element,
            xmi_id=ident,
            severity=severity,
        )
    )
