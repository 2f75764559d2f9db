"""Whether the model uses the profile at all: a model without one ACORDCS stereotype has nothing
to check, and every other check would pass it in silence."""

from __future__ import annotations

from collections.abc import Iterator

from acordcs.diagnostics import Diagnostic, diagnostic
from acordcs.model.checks import Context, check
from acordcs.profile import PROFILE_NAME
from acordcs.xmi.uml import Element

_PACKAGES = ("Model", "Package", "Profile")


@check
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


def _profile_definition(ctx: Context) -> Element | None:
    """The ACORDCS profile package defined in the file (BOUML exports it with the model)."""
    for element in ctx.uml.elements.values():
        if element.name == PROFILE_NAME and element.kind in _PACKAGES:
            return element
    return None
