"""A property of a running container set from another process (a console's hand): the property
found in the descriptor the container runs, and the value typed by the property's kind before the
container sees it. What :meth:`~acordcs.runtime.live.management.Management.set_property` checks.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from acordcs.runtime.errors import ConfigurationError

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application, Property

MAX_TEXT = 10000
"""Characters of a string property set this way."""


def model_property(app: Application, container: str, element: str, attribute: str) -> Property:
    """The property ``element.attribute`` (``element``: a component, ``Component.Port`` or a
    monitor hosted by ``container``) as the descriptor declares it, or ConfigurationError."""
    here = next((c for c in app.containers if c.name == container), None)
    hosted = {r.name for r in here.hosts} if here is not None else set()
    owner, _, port = element.partition(".")
    found: tuple[Property, ...] | None = None
    if owner in hosted:
        for comp in app.components:
            if comp.name == owner:
                if not port:
                    found = comp.properties
                elif (p := comp.port(port)) is not None:
                    found = p.properties
        for m in app.monitors:
            if m.name == owner and not port:
                found = m.properties
    prop = next((p for p in found or () if p.name == attribute), None)
    if prop is None:
        raise ConfigurationError(
            f"container {container!r} has no property {element!r:.80}.{attribute!r:.80} in the "
            "model it runs",
            hint="set a property of a component, port or monitor the container hosts",
        )
    return prop


def typed(prop: Property, value: object) -> object:
    """``value`` as property ``prop`` holds it (by its kind), or ConfigurationError."""
    kind = prop.kind
    what = f"{prop.qualified_name} is {'an' if kind == 'int' else 'a'} {kind}"
    if kind == "bool":
        if isinstance(value, bool):
            return value
    elif kind == "int":
        if isinstance(value, int) and not isinstance(value, bool) and -(2**63) <= value < 2**63:
            return value
    elif kind == "double":
        if isinstance(value, int) and not isinstance(value, bool) and abs(value) < 2**1023:
            return float(value)
        if isinstance(value, float) and math.isfinite(value):
            return value
    elif isinstance(value, str) and len(value) <= MAX_TEXT:
        return value
    raise ConfigurationError(f"{what}: not {value!r:.60}")
