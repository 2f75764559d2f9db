"""Whether the model uses the profile at all: a model without one ACORDCS stereotype has nothing
to check, and every other check would pass it in silence."""

from __future__ import annotations

import os
from collections.abc import Iterator
from urllib.parse import unquote

from acordcs.diagnostics import Diagnostic, diagnostic
from acordcs.model.checks.check_context import Context
from acordcs.profile import PROFILE_NAME
from acordcs.xmi.uml import Element

_PACKAGES = ("Model", "Package", "Profile")


def profile_applied(ctx: Context) -> Iterator[Diagnostic]:
    if ctx.arch.roles or any(a.profile == PROFILE_NAME for a in ctx.uml.applications.values()):
        return  # applied (wrongly applied stereotypes have their own codes: T301, T302)
    definition = _profile_definition(ctx)
    if definition is not None:
        found = (
            f"the profile {PROFILE_NAME} is in the file (line {definition.line}) but no element "
            "has one of its stereotypes: apply them (BOUML: the element's dialog, stereotype "
            f"{PROFILE_NAME}:CtxComponent...; Papyrus: Properties > Profile > Applied stereotypes)"
        )
    else:
        found = (
            f"the profile {PROFILE_NAME} is not in the file either: BOUML: import ACORDCS.xmi and "
            "apply its stereotypes; Papyrus: apply ACORDCS.profile.uml to the model "
            f"(acordcs-gen profile export DIR writes both), then apply its stereotypes"
        )
    if ctx.uml.applications:
        others = sorted({a.profile or a.name for a in ctx.uml.applications.values()})
        found += f" (the stereotypes applied are of: {', '.join(others[:5])})"
    roots = [e for e in ctx.uml.elements.values() if e.owner is None and e.kind in _PACKAGES]
    root = min(roots, key=lambda e: e.line) if roots else None
    yield diagnostic(
        "T313",
        f"no element has an ACORD-CS stereotype, so nothing was checked; {found}",
        file=ctx.uml.file,
        line=root.line if root is not None else 0,
        element=root.qualified_name() if root is not None else None,
        xmi_id=root.id if root is not None else None,
    )


def profile_files(ctx: Context) -> Iterator[Diagnostic]:
    """A profile applied by reference in an Eclipse UML2 model (Papyrus: ``appliedProfile
    href="ACORDCS.profile.uml#..."``) whose file is not where the reference says: Papyrus then
    cannot open the model's stereotypes. References to the tool's own libraries (``pathmap://``)
    and to the web are not files here; other tools' exports (MagicDraw's ``.mdzip``, Modelio's
    profile) name their project files, which an export is meant to be read without."""
    model = ctx.uml.file
    papyrus = ctx.uml.dialect == "eclipse-uml2" and ctx.uml.tool in (None, "papyrus")
    if not papyrus or not model or model == "-" or not os.path.isfile(model):
        return
    folder = os.path.dirname(os.path.abspath(model))
    for href, line in ctx.uml.profile_references:
        target = href.partition("#")[0]
        if not target or "://" in target or target.startswith("platform:"):
            continue
        path = unquote(target.removeprefix("file:"))
        if not os.path.isfile(os.path.join(folder, path)):
            where = os.path.normpath(path)
            yield diagnostic(
                "T321",
                f"the model applies the profile in {target!r}, which is not there ({where} from "
                "the model's folder); Papyrus will not show its stereotypes: put the profile file "
                "there (acordcs-gen profile export DIR --tool papyrus writes ACORDCS.profile.uml) "
                "or apply it again from where it is",
                file=model,
                line=line,
            )


def _profile_definition(ctx: Context) -> Element | None:
    """The ACORDCS profile package defined in the file (BOUML exports it with the model)."""
    for element in ctx.uml.elements.values():
        if element.name == PROFILE_NAME and element.kind in _PACKAGES:
            return element
    return None


CHECKS = (profile_applied, profile_files)
"""This module's checks, in the order they run."""
