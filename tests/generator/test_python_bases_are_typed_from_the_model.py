"""The ``python`` target types the base classes from the model: each operation's parameters and
return value by its UML types (int, integer, long, short -> int; double, float, real, number ->
float; bool, boolean -> bool; string -> str; any other type -> object, named in model_types.py
when its name can be a Python name; out parameters -> a tuple after the return value), and each
property as a typed attribute (ModelProperty, by its kind) unless its name is taken or no
identifier, which the base class lists in a comment and code reads with ``get``."""

from __future__ import annotations

import dataclasses
import typing
from pathlib import Path

import pytest

from acordcs.descriptor import Application, Operation, Parameter, Property
from acordcs.generator.targets.python import python
from acordcs.runtime.api import ModelProperty
from tests.support.generator import context, imported

r = dataclasses.replace

# UML type -> the annotation written, and what it evaluates to.
TYPES = {
    "int": ("int", int),
    "Integer": ("int", int),
    "long": ("int", int),
    "short": ("int", int),
    "double": ("float", float),
    "float": ("float", float),
    "Real": ("float", float),
    "number": ("float", float),
    "bool": ("bool", bool),
    "Boolean": ("bool", bool),
    "string": ("str", str),
    "String": ("str", str),
    "Image": ("model_types.Image", object),
    "Frame": ("model_types.Frame", object),
    "": ("object", object),
    "bytes": ("object", object),  # a builtin's name: not shadowed
    "_Hidden": ("object", object),
    "class": ("object", object),
    "x y": ("object", object),
    'Ty"""pe\n': ("object", object),
}


def generate(app: Application, tmp_path: Path) -> Path:
    ctx = context(app, tmp_path, target="python")
    python(ctx)
    out = tmp_path / "out"
    for f in ctx.files:
        (out / f.path).parent.mkdir(parents=True, exist_ok=True)
        (out / f.path).write_bytes(f.data)
    return out


def typed(weblab: Application) -> Application:
    """The WebLab with operations of every type in TYPES on Locomotion, one with out parameters,
    and properties whose names cannot be attributes."""
    loco = next(c for c in weblab.components if c.name == "Locomotion")
    ops = tuple(
        Operation(f"t{i}", f"take{i}", f"q::take{i}", (Parameter(f"p{i}", "value", uml),), uml)
        for i, uml in enumerate(TYPES)
    )
    outs = Operation(
        "o", "measure", "q::measure",
        (Parameter("a", "probe", "string"), Parameter("b", "level", "double", "out"),
         Parameter("c", "count", "int", "inout")),
        "bool",
    )  # fmt: skip
    odd = ("name", "get", "clock", "move", "on_LocomotionPort", "class", 'we"ird\nkey', "_x",
           "model_types", "str")  # fmt: skip
    props = (
        *loco.properties,
        *(Property(f"i{n}", n, f"q::{n}", "int", "int", 1) for n in odd),
        Property("f", "frame", "q::frame", "Image", "string", ""),
        Property("u", "untyped", "q::untyped", "", "string", ""),
    )
    loco = r(loco, operations=(*loco.operations, *ops, outs), properties=props)
    return r(
        weblab, components=tuple(loco if c.name == "Locomotion" else c for c in weblab.components)
    )


def test_operations_and_properties_carry_the_models_types(tmp_path: Path, weblab) -> None:
    out = generate(typed(weblab), tmp_path)
    text = (out / "weblab_app" / "base" / "Locomotion.py").read_text(encoding="utf-8")
    for i, (uml, (written, _)) in enumerate(TYPES.items()):
        returned = "None" if uml in ("", "void") else written
        assert f"    def take{i}(self, value: {written}) -> {returned}:\n" in text, uml
    assert "    def measure(self, probe: str, count: int) -> tuple[bool, float, int]:\n" in text
    assert "    def move(self, speed: float, turn: float) -> None:\n" in text
    assert "    def odometry(self) -> str:\n" in text
    assert (
        '    # Without an attribute (a name that is taken or no identifier): self.get("name"), '
        'self.get("get"), self.get("clock"), self.get("move"), self.get("on_LocomotionPort"), '
        'self.get("class"), self.get("we\\"ird\\nkey"), self.get("_x"), self.get("model_types"), '
        'self.get("str")\n'
    ) in text
    types = (out / "weblab_app" / "model_types.py").read_text(encoding="utf-8")
    assert "\nFrame: _typing.TypeAlias = object\n" in types
    assert "\nImage: _typing.TypeAlias = object\n" in types
    assert (
        '"""UML type Image, in Locomotion.frame, Locomotion.take12, Navigator.findStripe, Vision.grab.'
        in types
    )
    with imported(out, "weblab_app") as package:
        base = package.FACTORIES["Locomotion"].__bases__[0]
        for i, (uml, (_, evaluated)) in enumerate(TYPES.items()):
            hints = typing.get_type_hints(getattr(base, f"take{i}"))
            returned = type(None) if uml == "" else evaluated
            assert hints == {"value": evaluated, "return": returned}, uml
        attributes = {
            name: value.__orig_class__
            for name, value in vars(base).items()
            if isinstance(value, ModelProperty)
        }
        assert attributes == {
            "maxSpeed": ModelProperty[float],
            "wheelBase": ModelProperty[float],
            "frame": ModelProperty[package.model_types.Image],
            "untyped": ModelProperty[object],
        }


@pytest.mark.parametrize("sample", ["weblab", "smartroom"])
def test_every_property_of_the_samples_is_an_attribute_of_its_kind(
    tmp_path: Path, sample: str, request
) -> None:
    app: Application = request.getfixturevalue(sample)
    out = generate(app, tmp_path)
    kinds = {"int": int, "double": float, "bool": bool, "string": str}
    with imported(out, f"{sample}_app") as package:
        for comp in app.components:
            base = package.FACTORIES[comp.name].__bases__[0]
            for prop in comp.properties:
                attribute = vars(base)[prop.name]
                assert attribute.__orig_class__ == ModelProperty[kinds[prop.kind]], prop.name
                assert attribute.name == prop.name
