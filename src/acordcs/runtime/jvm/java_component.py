"""A component tagged ``language=java``, hosted by its container as a Python one is.

:func:`java_factory` makes the factory of such a component: its classes compiled
(:mod:`.javac_cache`), the JVM started (:mod:`.machine`), and a :class:`JavaComponent` class
made from the model (its properties with their typed defaults, its ports, its operations, as
:func:`acordcs.runtime.operations.generic_component` makes them) whose every operation calls the
Java object's method. The container sees a :class:`~acordcs.runtime.component.CtxComponent`: its
calls pass the interceptors, its properties are the container's (policies and monitors read and
write them), its ports are connected by the same connectors (in process, Pyro5).

The Java object gets a :class:`JavaHost` (the Java API's ``CtxComponent.Host``): each of its
ports gets a :class:`JavaPortLink` (``Port.Link``) through which it calls, notifies and pushes
straight to the component's port (the crossing into Python is the costly part of a Java
component's call: one per port call, with no port name or empty array to convert), its setters
set properties through the host, and
``ruleEngine(policySet)`` gives the paper's four calls over a policy set's engine
(:class:`JavaRules`). The container's properties are the truth: each change is written into the
Java object's field (``setProperty``) before its ``onPropertyChanged`` runs, and every field is
written at ``onStart`` (a replacement's restored state included). A Java exception is a
:class:`~.errors.JavaFault` with the component's part of the Java stack trace: the container
records it as a fault and goes on.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar, cast

from acordcs.java_names import identifier, method, package
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.jvm.deadlines import deadlines
from acordcs.runtime.jvm.errors import JavaFault, JavaHostError
from acordcs.runtime.jvm.java_values import to_java, to_python
from acordcs.runtime.jvm.javac_cache import compiled_classes
from acordcs.runtime.jvm.machine import java_class, start_jvm
from acordcs.runtime.operations import generic_component

if TYPE_CHECKING:
    from acordcs.descriptor.application import Component as ComponentDescription
    from acordcs.runtime.ports import Port

API = "org.acordcs.runtime"
DEFAULT_TIMEOUT = 5.0
"""Seconds a Java operation may run by default: what a remote caller waits by default."""
T = TypeVar("T")
_GLUE = ("jdk.internal.", "java.base/jdk.internal.", "org.jpype.", "java.lang.reflect.")


def java_stack(exc: BaseException) -> str:
    """The frames of a Java exception's stack trace down to where the host called in (the
    reflection and JPype frames below are the host's, not the component's)."""
    try:
        text = str(exc.stacktrace())  # type: ignore[attr-defined]
    except Exception:  # not a Java exception, or its trace cannot be read
        return ""
    kept = []
    for line in text.splitlines():
        if line.strip().startswith("at ") and line.strip()[3:].startswith(_GLUE):
            break
        kept.append(line)
    return "\n".join(kept[1:]) if kept else ""  # the first line is the message, said already


def fault(exc: BaseException, what: str) -> JavaFault:
    """A Java exception thrown in ``what`` as the fault the container records."""
    return JavaFault(f"{what} threw {exc}", java_stack(exc))


class JavaComponent(CtxComponent):
    """A hosted Java component: ``java`` is its Java object (of ``java_class``)."""

    java_class: ClassVar[Any]
    host_class: ClassVar[type[JavaHost]]  # JavaHost implementing the loaded CtxComponent.Host
    link_class: ClassVar[type[JavaPortLink]]  # JavaPortLink implementing the loaded Port.Link
    rules_class: ClassVar[type[JavaRules]]  # JavaRules implementing the loaded RuleEngine
    java_methods: ClassVar[tuple[str, ...]]  # the Java methods of the model's operations
    call_timeout: ClassVar[float]  # seconds an operation may run before it is interrupted
    java: Any
    methods: dict[str, Any]  # java_methods, bound to the Java object (looked up once)

    def __init__(self) -> None:
        import jpype

        cls = type(self)
        try:
            self.java = cls.java_class()
        except jpype.JException as exc:
            raise fault(exc, f"the constructor of {cls.java_class.__name__}") from None
        self.java.attachHost(cls.host_class(self))
        self.methods = {name: getattr(self.java, name) for name in cls.java_methods}

    def timed_out(self, operation: str, exc: BaseException | None) -> JavaFault:
        """The fault of ``operation``, interrupted at its call's timeout (``exc``: what it threw
        then; None: it returned, too late)."""
        # JPype raises an interrupted thread's status as an InterruptedException on the way
        # back, so a loop that stopped at the interrupt ends with one too
        ended = f"ended with {exc}" if exc is not None else "then returned, too late"
        return JavaFault(
            f"{self.name}.{operation} did not return within its call's timeout of "
            f"{self.call_timeout:g} s: its Java thread was interrupted, and it {ended}",
            java_stack(exc) if exc is not None else "",
        )

    def _java(self, what: str, call: Callable[[], Any]) -> Any:
        import jpype

        try:
            return call()
        except jpype.JException as exc:
            raise fault(exc, f"{self.name}.{what}") from None

    def on_start(self) -> None:
        def write_fields() -> None:
            for name, value in self.props.items():
                self.java.setProperty(name, to_java(value))

        self._java("setProperty", write_fields)
        self._java("onStart", self.java.onStart)

    def on_stop(self) -> None:
        self._java("onStop", self.java.onStop)

    def on_property_changed(self, name: str, old: object, new: object) -> None:
        self._java("setProperty", lambda: self.java.setProperty(name, to_java(new)))
        self._java(
            "onPropertyChanged",
            lambda: self.java.onPropertyChanged(name, to_java(old), to_java(new)),
        )


class JavaHost:
    """What a hosted Java object calls (the Java API's ``CtxComponent.Host``, implemented for
    each class loader by :func:`implementing`): the links of its ports, its property writes and
    its rule engines, with Python values."""

    def __init__(self, component: JavaComponent) -> None:
        self.component = component

    def link(self, port: Any) -> Any:
        return type(self.component).link_class(self.component, str(port))

    def set(self, prop: Any, value: Any) -> None:
        self.component.set(str(prop), to_python(value))

    def ruleEngine(self, policy_set: Any) -> Any:  # the Java interface names it so
        container: Any = self.component.container
        engine = container.policy_set(str(policy_set)).engine
        return type(self.component).rules_class(engine, self.component.name)


class JavaPortLink:
    """The container's end of one port of a hosted Java object (the Java API's ``Port.Link``):
    its calls, notifications and items go straight to the component's port. The Java object is
    made, and asks for its links, before the container gives the component its ports: the port
    is looked up at the first use."""

    def __init__(self, component: JavaComponent, port: str) -> None:
        self.component = component
        self.name = port
        self.port: Port | None = None

    def resolve(self) -> Port:
        self.port = self.component.port(self.name)
        return self.port

    def call0(self, operation: Any) -> Any:
        return to_java((self.port or self.resolve()).call(str(operation)))

    def call1(self, operation: Any, arg: Any) -> Any:
        return to_java((self.port or self.resolve()).call(str(operation), to_python(arg)))

    def call(self, operation: Any, args: Any) -> Any:
        values = [to_python(a) for a in args] if args is not None else []
        return to_java((self.port or self.resolve()).call(str(operation), *values))

    def notify(self, message: Any) -> None:
        (self.port or self.resolve()).notify(to_python(message))

    def push(self, item: Any) -> None:
        (self.port or self.resolve()).push(to_python(item))


class JavaRules:
    """The Java API's ``RuleEngine`` (``defrule``, ``set``, ``fire``, ``get``) over the engine of
    a policy set: the Java component's rules go to a rule set named after it."""

    def __init__(self, engine: Any, ruleset: str) -> None:
        self.engine = engine
        self.ruleset = ruleset

    def defrule(self, rule: Any) -> None:
        self.engine.defrule(str(rule), self.ruleset)

    def set(self, variable: Any, value: Any) -> None:
        self.engine.set(str(variable), to_python(value))

    def fire(self) -> None:
        self.engine.fire(self.ruleset)

    def get(self, variable: Any) -> Any:
        return to_java(self.engine.get(str(variable)))


def java_factory(
    comp: ComponentDescription,
    application: str,
    sources: Path | None,
    *,
    timeout: float = DEFAULT_TIMEOUT,
) -> ComponentFactory:
    """The factory of ``comp``, tagged ``language=java``, whose classes are in ``sources`` (the
    ``java`` target's output of application ``application``); JavaHostError when it cannot be
    hosted (said with the component's name and what to do). ``timeout``: seconds each of its
    operations may run before its Java thread is interrupted (:mod:`.deadlines`)."""
    who = f"component {comp.name!r} ({comp.qualified_name}, id {comp.id})"
    pkg, cls_name = package(application), identifier(comp.name)
    user = sources / pkg / f"{cls_name}.java" if sources is not None else None
    if sources is None or user is None or not user.is_file():
        raise JavaHostError(
            f"{who} is tagged language=java and its Java class "
            f"{'is missing' if sources is None else f'{user} is missing'}",
            hint="build the application with the java target (acordcs-gen build, its default "
            "targets), which writes java/<package>/<Component>.java once for your code",
        )
    start_jvm(who)
    classes = compiled_classes(sources, [user], who)
    jcls = java_class(classes, f"{pkg}.{cls_name}", who)
    base = java_class(classes, f"{API}.CtxComponent", who)
    if not issubclass(jcls, base):
        raise JavaHostError(
            f"{who}: the Java class {pkg}.{cls_name} does not extend {API}.CtxComponent",
            file=str(user),
            hint=f"declare it as in the first build: class {cls_name} extends {cls_name}Base",
        )
    model = generic_component(comp)
    namespace: dict[str, Any] = {
        "properties": model.properties,
        "ports": model.ports,
        "java_class": jcls,
        "call_timeout": float(timeout),
        "host_class": implementing(JavaHost, java_class(classes, f"{API}.CtxComponent$Host", who)),
        "link_class": implementing(JavaPortLink, java_class(classes, f"{API}.Port$Link", who)),
        "rules_class": implementing(JavaRules, java_class(classes, f"{API}.RuleEngine", who)),
        "__module__": __name__,
    }
    for op in comp.operations:
        name = method(op.name)
        if not hasattr(jcls, name):
            raise JavaHostError(
                f"{who}: its Java class {pkg}.{cls_name} has no method {name} for operation "
                f"{op.name!r} of the model",
                file=str(user),
                hint="rebuild the application (acordcs-gen build) and implement the method",
            )
        namespace[op.name] = _operation(op.name, name)
    namespace["java_methods"] = tuple(method(op.name) for op in comp.operations)
    for port in comp.ports:
        receives = port.kind == "asynchronous" or (
            port.kind == "stream" and port.role == "required"
        )
        if receives:
            namespace[f"on_{port.name}"] = _handler(port.name)
    cls = type(comp.name, (JavaComponent,), namespace)
    return ComponentFactory(comp.name, cls)


def implementing(cls: type[T], interface: Any) -> type[T]:
    """A subclass of ``cls`` implementing the Java ``interface`` (of one class loader) with its
    methods of the interface's names (JPype's ``JImplements``: a Java object of it is made with
    each instance; faster to call from Java than a ``JProxy``)."""
    import jpype

    names = {str(m.getName()) for m in interface.class_.getMethods()}
    body = {n: jpype.JOverride(getattr(cls, n)) for n in names if hasattr(cls, n)}
    return cast(type[T], jpype.JImplements(interface)(type(cls.__name__, (cls,), body)))


def _operation(operation: str, java_name: str) -> Callable[..., Any]:
    import jpype

    thrown = jpype.JException

    def call(self: JavaComponent, *args: Any) -> Any:
        running = deadlines.enter(self.call_timeout)
        try:
            result = self.methods[java_name](*args)
        except thrown as exc:
            if deadlines.leave(running):
                raise self.timed_out(operation, exc) from None
            raise fault(exc, f"{self.name}.{operation}") from None
        except BaseException:
            deadlines.leave(running)
            raise
        if deadlines.leave(running):
            raise self.timed_out(operation, None)
        return to_python(result)

    call.__name__ = call.__qualname__ = operation
    return call


def _handler(port: str) -> Callable[..., Any]:
    def deliver(self: JavaComponent, message: Any) -> None:
        self._java("onMessage", lambda: self.java.onMessage(port, to_java(message)))

    deliver.__name__ = f"on_{port}"
    return deliver
