"""Components from the application descriptor: the generic class of a component no factory
implements, with the model's properties, ports and operations.

A generic component runs (its properties are rule variables, its ports connect) and has every
operation the model declares, with the model's parameters, so crisp rules calling them bind; calling
one raises :class:`~acordcs.runtime.errors.OperationNotImplementedError` naming the component and the
operation: its code comes from a factory (``assemble(..., factories={name: cls})``).
"""

from __future__ import annotations

import inspect
import keyword
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from acordcs.runtime.component import CtxComponent
from acordcs.runtime.errors import ConfigurationError, OperationNotImplementedError
from acordcs.runtime.ports import PortSpec

if TYPE_CHECKING:
    from acordcs.descriptor.model import Component, Operation

# Names a generic operation cannot take: the component API every component inherits.
_RESERVED = frozenset(dir(CtxComponent))


def signature(op: Operation) -> inspect.Signature:
    """The Python signature of a model operation: its ``in`` and ``inout`` parameters, in order."""
    return inspect.Signature(
        [
            inspect.Parameter(p.name, inspect.Parameter.POSITIONAL_OR_KEYWORD)
            for p in op.parameters
            if p.direction in ("in", "inout")
        ]
    )


def generic_component(component: Component) -> type[CtxComponent]:
    """A component class made from the model: its properties (with their defaults), its ports and
    its operations (each raising OperationNotImplementedError when called)."""
    props = {p.name: p.default for p in component.properties}
    ports = tuple(PortSpec(p.name, p.kind, p.role) for p in component.ports)
    namespace: dict[str, Any] = {"properties": props, "ports": ports}
    overloads: dict[str, list[Operation]] = {}
    for op in component.operations:
        if not op.name.isidentifier() or keyword.iskeyword(op.name) or op.name.startswith("_"):
            raise ConfigurationError(
                f"operation {op.name!r} of component {component.name!r} is not a Python name",
                hint="rename the operation in the model, or install a factory for the component",
            )
        if op.name in _RESERVED:
            raise ConfigurationError(
                f"operation {op.name!r} of component {component.name!r} would hide the component "
                f"API ({op.name}() of every CtxComponent)",
                hint="rename the operation in the model, or install a factory for the component",
            )
        overloads.setdefault(op.name, []).append(op)
    for name, ops in overloads.items():
        namespace[name] = _unimplemented(component.name, ops)
    return type(component.name, (CtxComponent,), namespace)


def _unimplemented(component: str, ops: list[Operation]) -> Callable[..., Any]:
    """A method standing for a model operation (one or several overloads) without code."""
    signatures = [signature(op) for op in ops]
    shown = " or ".join(f"{ops[0].name}({', '.join(s.parameters)})" for s in signatures)

    def operation(self: CtxComponent, *args: Any, **kwargs: Any) -> Any:
        # Wrong arguments are the caller's error, reported as Python reports them.
        problems = []
        for sig in signatures:
            try:
                sig.bind(*args, **kwargs)
                break
            except TypeError as exc:
                problems.append(str(exc))
        else:
            raise TypeError(f"{shown}: {'; '.join(problems)}")
        raise OperationNotImplementedError(
            f"component {self.name!r} has no code for operation {shown}: the model declares it, "
            "no factory implements it",
            where=f"container {self.container.name!r}",
            hint=f"install a factory for the component: assemble(..., factories={{{component!r}: "
            f"YourClass}}) where YourClass(CtxComponent) defines {ops[0].name}()",
        )

    operation.__name__ = ops[0].name
    operation.__qualname__ = f"{component}.{ops[0].name}"
    operation.__doc__ = "\n\n".join(op.documentation for op in ops if op.documentation) or None
    if len(signatures) == 1:
        self_param = inspect.Parameter("self", inspect.Parameter.POSITIONAL_OR_KEYWORD)
        params = [self_param, *signatures[0].parameters.values()]
        operation.__signature__ = inspect.Signature(params)  # type: ignore[attr-defined]
    return operation
