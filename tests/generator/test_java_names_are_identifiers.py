"""The ``java`` target makes Java names of model names: the package is the application's name in
lower case made an identifier (keywords get ``_``), members keep the model's name made an
identifier, accessors named like Object's or CtxComponent's methods get ``_``, an operation the
model declares as a setter replaces the generated one, and names that would still collide stop
the target with a message saying which."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

from acordcs.descriptor import Application
from acordcs.descriptor.application import Operation, Parameter, Property
from acordcs.generator.errors import BuildError
from acordcs.generator.targets import targets
from tests.support.generator import context

r = dataclasses.replace


def generate(app: Application, tmp_path: Path) -> dict[str, str]:
    made = context(app, tmp_path, target="java")
    targets()["java"].run(made)
    return {f.path: f.data.decode("ascii") for f in made.files}


@pytest.mark.parametrize(
    ("name", "package"),
    [
        ("WebLab", "weblab"),
        ("Class", "class_"),
        ("2nd Lab", "_2nd_lab"),
        ("\u00c9t\u00e9", "_t_"),
        ("java", "java_"),
        ("var", "var_"),
    ],
)
def test_the_package_is_the_application_name_made_an_identifier(
    tmp_path: Path, weblab, name: str, package: str
):
    files = generate(r(weblab, name=name), tmp_path)
    assert f"java/{package}/AccessBase.java" in files
    lines = files[f"java/{package}/Access.java"].splitlines()
    assert next(line for line in lines if not line.startswith("//")) == f"package {package};"


def prop(name: str, kind: str = "int", default=0, type_: str = "") -> Property:
    return Property(f"id-{name}", name, f"M::C::{name}", type_ or kind, kind, default)


def test_keywords_and_taken_method_names_get_an_underscore(tmp_path: Path, weblab):
    access = r(
        weblab.components[0],
        properties=(
            prop("class"),
            prop("Class_x", "double", 1.5),
            prop("big", "int", 2**40),
            prop("flag", "bool", True),
        ),
        operations=(
            Operation("o1", "wait", "M::C::wait"),
            Operation("o2", "default", "M::C::default", (Parameter("p", "new", "long"),), "real"),
        ),
    )
    files = generate(r(weblab, components=(access, *weblab.components[1:])), tmp_path)
    base = files["java/weblab/AccessBase.java"]
    for line in (
        "    protected int class_ = 0;",
        "    public int getClass_() {",
        "    public void setClass_(int value) {",
        "    protected double Class_x = 1.5;",
        "    protected long big = 1099511627776L;",
        "    protected boolean flag = true;",
        "    public abstract void wait_();",
        "    public abstract double default_(long new_);",
        '            case "class": this.class_ = asInt(property, value); return;',
    ):
        assert line in base.splitlines(), line


def test_an_operation_declared_as_setter_replaces_the_generated_one(tmp_path: Path, smartroom):
    files = generate(smartroom, tmp_path)
    base = files["java/smartroom/HvacBase.java"]
    assert "    public abstract void setSetpoint(double celsius);" in base
    assert "    public void setSetpoint(double value) {" not in base
    assert "    public double getSetpoint() {" in base


def test_names_that_still_collide_stop_the_target(tmp_path: Path, weblab):
    access = r(weblab.components[0], properties=(prop("a-b"), prop("a_b")))
    with pytest.raises(BuildError, match=r"Java names would collide: a_b"):
        generate(r(weblab, components=(access, *weblab.components[1:])), tmp_path)
    twins = r(weblab.components[1], name="AccessBase")
    with pytest.raises(BuildError, match=r"Java class names of components would collide"):
        generate(r(weblab, components=(weblab.components[0], twins)), tmp_path)


NAMES = ("wait", "default", "ruleEngine", "onStart", "x-y", "2nd", "\u00e9t\u00e9", "var", "java")


def test_the_java_host_names_classes_and_methods_as_the_stylesheet_does(tmp_path: Path, weblab):
    """The host (``acordcs.java_names``) finds the class and the methods the
    stylesheet wrote, for names that are keywords, taken, or not identifiers at all."""
    from acordcs.java_names import identifier, method, package

    ops = tuple(Operation(f"o{i}", n, f"M::C::{n}") for i, n in enumerate(NAMES))
    comps = (r(weblab.components[0], name="class", operations=ops), *weblab.components[1:])
    files = generate(r(weblab, name="Lab 2", components=comps), tmp_path)
    user = f"java/{package('Lab 2')}/{identifier('class')}.java"
    assert user == "java/lab_2/class_.java" and user in files
    declared = set(re.findall(r"public void (\w+)\(\)", files[user]))
    assert declared == {method(n) for n in NAMES}
    assert {method(n) for n in ("wait", "default", "ruleEngine", "onStart")} == {
        "wait_", "default_", "ruleEngine_", "onStart_"}  # fmt: skip
