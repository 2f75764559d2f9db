"""Components, their factories, and the handles callers hold (paper, section 3: lightweight model).

A component class derives from :class:`CtxComponent`, declares its ``properties`` (defaults, the
attributes rules read and write) and ``ports``; its public methods are its operations. A
:class:`ComponentFactory` creates, destroys and finds instances of one component type; containers
install and remove factories at run time. Callers never hold the instance: they hold a
:class:`ComponentRef`, whose calls go through the container (interceptors, events) and which fails
cleanly once the component is destroyed, but keeps working across a replacement.

A container hosts an instance by :func:`attach_component` and keeps a :class:`Hosted` record of it;
components and handles reach their container through :class:`ComponentHost`.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, Generic, Protocol, TypeVar, cast, overload

from acordcs.runtime.callgate import CallGate
from acordcs.runtime.errors import ComponentDestroyedError, FactoryError, PortError
from acordcs.runtime.ports import Port, PortHost, PortSpec

if TYPE_CHECKING:
    from acordcs.runtime.clock import Clock


class ComponentHost(PortHost, Protocol):
    """What a component, its ports and the handles on it need from the container hosting it."""

    def get_property(self, element: str, attribute: str) -> object: ...

    def set_property(self, element: str, attribute: str, value: object) -> None: ...

    def publish_context(self, publisher: str, document: object) -> int: ...

    def invoke(
        self,
        name: str,
        operation: str,
        args: tuple[Any, ...] = (),
        kwargs: dict[str, Any] | None = None,
        *,
        lineage: int | None = None,
    ) -> Any: ...

    def instance(self, name: str, lineage: int | None = None) -> CtxComponent:
        """The live instance (of that lineage); raises once it is destroyed."""
        ...


class CtxComponent:
    """Base class of components.

    Subclasses declare ``properties`` (name -> default), ``ports`` (PortSpecs) and optionally
    ``state_fields`` (plain attributes saved with the state besides the properties). Override
    :meth:`save_state` / :meth:`restore_state` for state that is neither. Hooks: :meth:`on_start`
    after creation (or replacement), :meth:`on_stop` before destruction,
    :meth:`on_property_changed` after a property changed.
    """

    properties: ClassVar[dict[str, object]] = {}
    ports: ClassVar[tuple[PortSpec, ...]] = ()
    state_fields: ClassVar[tuple[str, ...]] = ()

    # Set by the container when it hosts the instance (attach_component).
    name: str
    container: ComponentHost
    factory: ComponentFactory
    props: dict[str, object]
    port_map: dict[str, Port]
    alive: bool = False

    # ------------------------------------------------------------------------------ the API
    @property
    def clock(self) -> Clock:
        return self.container.clock

    @property
    def type_name(self) -> str:
        return self.factory.type_name

    def get(self, attribute: str) -> object:
        return self.container.get_property(self.name, attribute)

    def set(self, attribute: str, value: object) -> None:
        """Change a property through the container, so policies and monitors see it."""
        self.container.set_property(self.name, attribute, value)

    def publish_context(self, document: object) -> int:
        """Publish ``document`` (XML as bytes, text or an lxml element) to the context provider as
        this component's latest context: the subscribing monitors whose xpath selects something
        in it read it. Returns its sequence number."""
        return self.container.publish_context(self.name, document)

    def port(self, name: str) -> Port:
        try:
            return self.port_map[name]
        except KeyError:
            known = ", ".join(self.port_map) or "none"
            raise PortError(
                f"component {self.name!r} has no port {name!r} (ports: {known})",
                where=f"container {self.container.name!r}",
            ) from None

    def save_state(self) -> dict[str, Any]:
        """The state to carry across a replacement (or to persist): properties and state fields."""
        return {
            "properties": copy.deepcopy(self.props),
            "fields": {
                f: copy.deepcopy(getattr(self, f)) for f in self.state_fields if hasattr(self, f)
            },
        }

    def restore_state(self, state: dict[str, Any]) -> None:
        """Take over a saved state; properties this type does not declare are ignored."""
        for key, value in state.get("properties", {}).items():
            if key in self.props:
                self.props[key] = copy.deepcopy(value)
        for key, value in state.get("fields", {}).items():
            if key in type(self).state_fields:
                setattr(self, key, copy.deepcopy(value))

    def on_start(self) -> None:
        """Called once hosted (ports and properties ready)."""

    def on_stop(self) -> None:
        """Called before the component is destroyed or replaced."""

    def on_property_changed(self, name: str, old: object, new: object) -> None:
        """Called after one of this component's properties changed value (a policy set's action,
        another component, the component itself), once the change's event has been delivered.
        Runs on the thread that made the change: keep it short. An exception is recorded as a
        fault of this component; the change stands."""

    @classmethod
    def operation_names(cls) -> frozenset[str]:
        """Public methods of the subclass: the operations callers and rules may invoke."""
        base = set(dir(CtxComponent))
        return frozenset(
            n
            for n in dir(cls)
            if not n.startswith("_") and n not in base and callable(getattr(cls, n, None))
        )


T = TypeVar("T")


class ModelProperty(Generic[T]):
    """A property of the model as a typed attribute of a component class: ``self.maxSpeed`` reads
    ``self.get("maxSpeed")`` and ``self.maxSpeed = v`` is ``self.set("maxSpeed", v)``, through the
    container (policies and monitors see the change). The generated base classes declare one per
    property, typed by the model (``maxSpeed = ModelProperty[float]("maxSpeed")``), so that code
    using them needs no cast. The value is what the container holds: the model's default, what a
    policy set wrote (an engine's number rounded for an ``int`` property) or what code set; it is
    not converted on reading."""

    def __init__(self, name: str) -> None:
        self.name = name

    def __repr__(self) -> str:
        return f"<ModelProperty {self.name}>"

    @overload
    def __get__(self, instance: None, owner: type[Any]) -> ModelProperty[T]: ...

    @overload
    def __get__(self, instance: CtxComponent, owner: type[Any]) -> T: ...

    def __get__(self, instance: CtxComponent | None, owner: type[Any]) -> ModelProperty[T] | T:
        if instance is None:
            return self
        return cast(T, instance.get(self.name))

    def __set__(self, instance: CtxComponent, value: T) -> None:
        instance.set(self.name, value)


def attach_component(
    instance: CtxComponent, name: str, container: ComponentHost, factory: ComponentFactory
) -> None:
    """Make ``instance`` the component ``name`` of ``container``: its properties (copies of the
    class defaults) and ports. A function, not a method: a component's public methods are its
    operations."""
    cls = type(instance)
    instance.name = name
    instance.container = container
    instance.factory = factory
    instance.props = copy.deepcopy(dict(cls.properties))
    instance.port_map = {}
    for spec in cls.ports:
        if spec.name in instance.port_map:
            raise PortError(f"{cls.__name__} declares port {spec.name!r} twice")
        instance.port_map[spec.name] = Port(instance, spec)
    instance.alive = True


@dataclass(slots=True)
class Hosted:
    """A container's record of a component it hosts: the instance (replaced in place by
    ``replace``), the lineage its handles carry, its operations, and the gate its calls pass."""

    instance: CtxComponent
    lineage: int
    operations: frozenset[str]
    gate: CallGate = field(default_factory=CallGate)


class ComponentFactory:
    """Creates, destroys and finds the instances of one component type.

    ``create`` builds an instance (default: ``cls()``); ``destroy`` releases what the instance holds
    (default: nothing beyond :meth:`CtxComponent.on_stop`). Instances remember their factory, so
    they can be destroyed even after the factory was removed from the container.
    """

    def __init__(
        self,
        type_name: str,
        cls: type[CtxComponent],
        *,
        create: Callable[..., CtxComponent] | None = None,
        destroy: Callable[[CtxComponent], None] | None = None,
    ) -> None:
        if not (isinstance(cls, type) and issubclass(cls, CtxComponent)):
            raise FactoryError(
                f"factory {type_name!r}: {cls!r} is not a CtxComponent subclass",
                hint="derive the component class from acordcs.runtime.CtxComponent",
            )
        self.type_name = type_name
        self.cls = cls
        self._create = create or (lambda **config: cls(**config))
        self._destroy = destroy
        self.instances: dict[str, CtxComponent] = {}

    def __repr__(self) -> str:
        return (
            f"<ComponentFactory {self.type_name} ({self.cls.__name__}), {len(self.instances)} live>"
        )

    def create(self, **config: Any) -> CtxComponent:
        instance = self._create(**config)
        if not isinstance(instance, self.cls):
            raise FactoryError(
                f"factory {self.type_name!r} built a {type(instance).__name__}, not a {self.cls.__name__}"
            )
        return instance

    def adopt(self, instance: CtxComponent) -> None:
        self.instances[instance.name] = instance

    def destroy(self, instance: CtxComponent) -> None:
        self.instances.pop(instance.name, None)
        if self._destroy is not None:
            self._destroy(instance)

    def find(self, name: str) -> CtxComponent | None:
        return self.instances.get(name)


class ComponentRef:
    """A caller's handle on a hosted component: ``ref.operation(*args)`` goes through the container.

    The handle follows its component across replacements (same lineage) and raises
    :class:`ComponentDestroyedError` once the component is destroyed, even if a new component later
    takes the same name.
    """

    __slots__ = ("_container", "_lineage", "_name")

    def __init__(self, container: ComponentHost, name: str, lineage: int) -> None:
        object.__setattr__(self, "_container", container)
        object.__setattr__(self, "_name", name)
        object.__setattr__(self, "_lineage", lineage)

    @property
    def name(self) -> str:
        return self._name

    @property
    def instance(self) -> CtxComponent:
        """The live instance (for tests and tools; calls on it bypass interceptors)."""
        return self._container.instance(self._name, self._lineage)

    @property
    def type_name(self) -> str:
        return self.instance.type_name

    def call(self, operation: str, *args: Any, **kwargs: Any) -> Any:
        return self._container.invoke(self._name, operation, args, kwargs, lineage=self._lineage)

    def get(self, attribute: str) -> object:
        self._container.instance(self._name, self._lineage)  # raises once destroyed
        return self._container.get_property(self._name, attribute)

    def set(self, attribute: str, value: object) -> None:
        self._container.instance(self._name, self._lineage)  # raises once destroyed
        self._container.set_property(self._name, attribute, value)

    def port(self, name: str) -> Port:
        return self.instance.port(name)

    @property
    def alive(self) -> bool:
        try:
            self._container.instance(self._name, self._lineage)
        except ComponentDestroyedError:
            return False
        return True

    def __getattr__(self, operation: str) -> Callable[..., Any]:
        if operation.startswith("_"):
            raise AttributeError(operation)

        def bound(*args: Any, **kwargs: Any) -> Any:
            return self._container.invoke(
                self._name, operation, args, kwargs, lineage=self._lineage
            )

        bound.__name__ = operation
        return bound

    def __setattr__(self, key: str, value: object) -> None:
        raise AttributeError(f"set properties with ref.set({key!r}, value); handles are read-only")

    def __repr__(self) -> str:
        return f"<ComponentRef {self._name} in {self._container.name}>"

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, ComponentRef)
            and other._container is self._container
            and other._name == self._name
            and other._lineage == self._lineage
        )

    def __hash__(self) -> int:
        return hash((id(self._container), self._name, self._lineage))
