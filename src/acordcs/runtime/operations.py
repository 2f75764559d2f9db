"""Components from the application descriptor: the generic class of a component no factory
implements (its properties and ports as the model declares them).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from acordcs.runtime.component import CtxComponent
from acordcs.runtime.ports import PortSpec

if TYPE_CHECKING:
    from acordcs.descriptor.model import Component


def generic_component(component: Component) -> type[CtxComponent]:
    """A component class made from the model: its properties (with their defaults) and ports."""
    props = {p.name: p.default for p in component.properties}
    ports = tuple(PortSpec(p.name, p.kind, p.role) for p in component.ports)
    return type(component.name, (CtxComponent,), {"properties": props, "ports": ports})
