"""Model operations at run time: how their parameters map to Python, and the generic class of a
component no factory implements.

The mapping of a model operation to a Python method (what a factory's class implements):

- the arguments are the ``in`` and ``inout`` parameters, in the model's order (by position or by
  name; :func:`signature`);
- an operation without ``out`` or ``inout`` parameters returns its return value (None when it has
  no return type);
- an operation with ``out`` or ``inout`` parameters returns a tuple: its return value (None when it
  has no return type), then the final value of each ``out`` and ``inout`` parameter in the model's
  order (:func:`out_parameters`). ``find(in frame, out x, inout y): bool`` is
  ``def find(self, frame, y)`` returning ``(found, x, y)``. Over Pyro5 the tuple stays a tuple.

``assemble`` checks the results of such operations (:class:`OutParameters`): a result of another
shape is a fault of the call, recorded and logged; the caller still gets what was returned.

A generic component runs (its properties are rule variables, its ports connect) and has every
operation the model declares, with the model's parameters, so crisp rules calling them bind; calling
one raises :class:`~acordcs.runtime.errors.OperationNotImplementedError` naming the component and the
operation: its code comes from a factory (``assemble(..., factories={name: cls})``).

A method standing for an operation without code (a generic component's, a generated base class's)
is marked :func:`unimplemented`; :func:`has_code` tells whether a class implements an operation
(a container's start lists the operations that the model calls and that have none:
:mod:`acordcs.runtime.live.code_check`).
"""

from __future__ import annotations

import inspect
import keyword
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, TypeVar

from acordcs.runtime.component import CtxComponent
from acordcs.runtime.errors import (
    ConfigurationError,
    OperationNotImplementedError,
    RuntimeFailure,
)
from acordcs.runtime.interceptors import Interceptor, Invocation
from acordcs.runtime.ports import PortSpec
from acordcs.vocabularies import ARGUMENT_DIRECTIONS, RESULT_DIRECTIONS

if TYPE_CHECKING:
    from acordcs.descriptor.application import Component, Operation, Port

# Names a generic operation cannot take: the component API every component inherits.
_RESERVED = frozenset(dir(CtxComponent))

F = TypeVar("F", bound=Callable[..., Any])

# The mark unimplemented() leaves on a method.
_UNIMPLEMENTED = "__acordcs_unimplemented__"


def unimplemented(method: F) -> F:
    """Mark ``method`` as standing for a model operation that has no code (it raises
    OperationNotImplementedError): a subclass implements the operation by overriding it."""
    setattr(method, _UNIMPLEMENTED, True)
    return method


def has_code(cls: type, operation: str) -> bool:
    """True when ``cls`` has a method ``operation`` that is not marked :func:`unimplemented` (a
    generated base's method the user's class does not override is not code)."""
    method = getattr(cls, operation, None)
    return callable(method) and not getattr(method, _UNIMPLEMENTED, False)


def signature(op: Operation) -> inspect.Signature:
    """The Python signature of a model operation: its ``in`` and ``inout`` parameters, in order.
    Raises ConfigurationError for a parameter name Python cannot take (``from``, ``x y``)."""
    params = []
    for p in op.parameters:
        if p.direction not in ARGUMENT_DIRECTIONS:
            continue
        try:
            params.append(inspect.Parameter(p.name, inspect.Parameter.POSITIONAL_OR_KEYWORD))
        except ValueError:
            raise ConfigurationError(
                f"parameter {p.name!r} of operation {op.qualified_name or op.name} is not a "
                "Python name",
                hint="rename the parameter in the model",
            ) from None
    return inspect.Signature(params)


def out_parameters(op: Operation) -> tuple[str, ...]:
    """Names of the ``out`` and ``inout`` parameters of ``op``, in order: the values its result
    carries after its return value (none: the result is the return value itself)."""
    return tuple(p.name for p in op.parameters if p.direction in RESULT_DIRECTIONS)


def result_shape(op: Operation) -> str:
    """What a call of ``op`` returns, as the mapping says (for messages and docstrings)."""
    outs = out_parameters(op)
    if not outs:
        return "its return value" if op.return_type else "None"
    return f"(return value, {', '.join(outs)})"


class OutParameters(Interceptor):
    """Checks the results of the operations of one component that have ``out`` or ``inout``
    parameters: a tuple of the return value and the out values. A result of another shape raises
    here, which the container records as a fault of this interceptor; the call goes on."""

    def __init__(self, component: str, operations: Iterable[Operation]) -> None:
        self.name = f"out-parameters:{component}"
        self.component = component
        # operation name -> accepted tuple lengths (overloads may differ)
        self.lengths: dict[str, set[int]] = {}
        self.shapes: dict[str, list[str]] = {}
        for op in operations:
            outs = out_parameters(op)
            if outs:
                self.lengths.setdefault(op.name, set()).add(1 + len(outs))
                self.shapes.setdefault(op.name, []).append(result_shape(op))

    def after(self, call: Invocation) -> None:
        lengths = self.lengths.get(call.operation)
        if lengths is None or call.error is not None:
            return
        result = call.result
        if isinstance(result, tuple | list) and len(result) in lengths:
            return
        raise TypeError(
            f"{self.component}.{call.operation}() returned {result!r}; its out parameters map to "
            f"a tuple {' or '.join(self.shapes[call.operation])} (see acordcs.runtime.operations)"
        )


def generic_component(component: Component) -> type[CtxComponent]:
    """A component class made from the model: its properties (with their defaults), its ports (with
    the rate, capacity and overflow the model gives them) and its operations (each raising
    OperationNotImplementedError when called)."""
    props = {p.name: p.default for p in component.properties}
    ports = tuple(_port_spec(p) for p in component.ports)
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


def _port_spec(port: Port) -> PortSpec:
    """A port as the model declares it; its ``rate``, ``capacity`` and ``overflow`` properties, if
    it has them, set the port's (its other properties are added at assembly)."""
    settings: dict[str, Any] = {}
    for p in port.properties:
        if p.name == "rate" and p.kind in ("int", "double"):
            settings["rate"] = float(p.default)
        elif p.name == "capacity" and p.kind == "int":
            settings["capacity"] = p.default
        elif p.name == "overflow" and p.kind == "string":
            settings["overflow"] = p.default
    try:
        return PortSpec(port.name, port.kind, port.role, **settings)
    except RuntimeFailure as exc:
        raise ConfigurationError(
            f"port {port.qualified_name}: {exc.message}",
            hint="fix the port's property default in the model",
        ) from None


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

    unimplemented(operation)
    operation.__name__ = ops[0].name
    operation.__qualname__ = f"{component}.{ops[0].name}"
    docs = [op.documentation for op in ops if op.documentation]
    docs.append(" or ".join(f"Returns {result_shape(op)}." for op in ops))
    operation.__doc__ = "\n\n".join(docs)
    if len(signatures) == 1:
        self_param = inspect.Parameter("self", inspect.Parameter.POSITIONAL_OR_KEYWORD)
        params = [self_param, *signatures[0].parameters.values()]
        operation.__signature__ = inspect.Signature(params)  # type: ignore[attr-defined]
    return operation
