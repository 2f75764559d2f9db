"""ModelProperty: a model property as a typed attribute of a component class. Reading it reads the
container's value, writing it sets the property through the container (an event policies and
monitors see), on the class it is the descriptor itself, and it is not an operation."""

from __future__ import annotations

from acordcs.runtime import events as ev
from acordcs.runtime.api import ComponentFactory, Container, CtxComponent, ModelProperty
from acordcs.runtime.clock import VirtualClock


class Lamp(CtxComponent):
    properties = {"level": 0.5, "label": "desk"}  # noqa: RUF012 (CtxComponent declares it a ClassVar)
    level = ModelProperty[float]("level")
    label = ModelProperty[str]("label")

    def dim(self) -> float:
        self.level = self.level / 2
        return self.level


def test_reads_and_writes_go_through_the_container() -> None:
    box = Container("box", clock=VirtualClock())
    seen: list[tuple[str | None, object]] = []
    box.subscribe(ev.PROPERTY_CHANGED, lambda e: seen.append((e.attribute, e.value)), name="t")
    box.install_factory(ComponentFactory("Lamp", Lamp))
    ref = box.create("Lamp", "lamp")
    try:
        lamp = ref.instance
        assert isinstance(lamp, Lamp)
        assert (lamp.level, lamp.label) == (0.5, "desk")
        box.set_property("lamp", "level", 0.8)  # a policy's write: the attribute reads it
        assert lamp.level == 0.8
        assert ref.dim() == 0.4  # through the container, as a caller calls it
        assert box.get_property("lamp", "level") == 0.4
        lamp.label = "hall"
        assert ref.get("label") == "hall"
        assert seen == [("level", 0.8), ("level", 0.4), ("label", "hall")]
    finally:
        box.close()


def test_on_the_class_it_is_the_descriptor_and_no_operation() -> None:
    assert isinstance(Lamp.level, ModelProperty) and Lamp.level.name == "level"
    assert Lamp.operation_names() == frozenset({"dim"})
