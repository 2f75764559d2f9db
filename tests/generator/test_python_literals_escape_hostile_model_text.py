"""Whatever the model's documentation, defaults, types, hosts and names hold, the ``python``
target's files parse, and every string from the model reads back in Python as the model wrote it
(docstrings line by line); a name that cannot be Python code is refused with G703 before anything
is written."""

from __future__ import annotations

import ast
import dataclasses
import inspect
from pathlib import Path

import pytest

from acordcs.descriptor import Application, Operation, Parameter, Property
from acordcs.generator.errors import BuildError
from acordcs.generator.targets.python import package_name, python
from acordcs.runtime.errors import OperationNotImplementedError
from tests.support.generator import context, imported

r = dataclasses.replace

HOSTILE = [
    'a """ b',
    "triple single ''' here",
    "ends in a backslash \\",
    'ends in a quote "',
    "line1\nline2\r\nline3 \ttab",
    "non-ASCII: é 中 😀 line\u2028separator zero\u200bwidth e\u0301",
    "escapes as text: \\n \\x00 \\u0041 \\N{DASH} %s {braces} {{}}",
    "#!/bin/sh\nimport os; os.system('x')  # code?",
]
TEXT = "\n".join(HOSTILE)


def hostile(app: Application) -> Application:
    loco = next(c for c in app.components if c.name == "Locomotion")
    props = (
        *loco.properties,
        *(
            Property(f"id{i}", f"p{i}", f"q::p{i}", "string\n# x", "string", s, s)
            for i, s in enumerate(HOSTILE)
        ),
        Property("i1", "big", "q::big", "int", "int", -(10**30)),
        Property("i2", "huge", "q::huge", "double", "double", 1.7976931348623157e308),
        Property("i3", "tiny", "q::tiny", "double", "double", -1.5e-300),
        Property("i4", "flag", "q::flag", "bool", "bool", True),
        Property("i5", 'we"ird\nkey', "q::k", "string", "string", ""),
    )
    ops = (
        *(r(op, documentation=TEXT) for op in loco.operations),
        Operation("o2", "move", "q::move2", (Parameter("p", "speed", 'Ty"""pe\n'),), "x\ny"),
    )
    ports = tuple(r(p, documentation=TEXT) for p in loco.ports)
    loco = r(loco, documentation=TEXT, properties=props, operations=ops, ports=ports)
    components = tuple(loco if c.name == "Locomotion" else c for c in app.components)
    containers = tuple(
        r(c, host='h"o\\st\n', documentation=TEXT, qualified_name=c.qualified_name + "\n#x")
        for c in app.containers
    )
    monitors = tuple(
        r(
            m,
            documentation=TEXT,
            xpath=TEXT if m.acquisition == "subscribe" else m.xpath,
            properties=(*m.properties, Property("im", "note", "q::note", "string", "string", TEXT)),
        )
        for m in app.monitors
    )
    return r(
        app,
        name='We"b\\Lab """',
        components=components,
        containers=containers,
        monitors=monitors,
    )


def generate(app: Application, tmp_path: Path) -> Path:
    ctx = context(app, tmp_path, target="python", source='m"\n.xmi')
    python(ctx)
    out = tmp_path / "out"
    for f in ctx.files:
        (out / f.path).parent.mkdir(parents=True, exist_ok=True)
        (out / f.path).write_bytes(f.data)
    return out


def doc_lines(text: str) -> list[str]:
    return [line.strip() for line in text.replace("\r\n", "\n").split("\n")]


def contains(lines: list[str], part: list[str]) -> bool:
    return any(lines[i : i + len(part)] == part for i in range(len(lines)))


def test_hostile_text_parses_and_reads_back(tmp_path: Path, weblab):
    app = hostile(weblab)
    out = generate(app, tmp_path)
    package = package_name(app.name)
    assert package == "we_b_lab_____app"
    files = sorted(out.rglob("*.py"))
    assert files
    for path in files:
        ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    with imported(out, package) as pkg:
        assert app.name == pkg.APPLICATION
        assert pkg.descriptor() == app
        base = pkg.FACTORIES["Locomotion"].__bases__[0]
        loco = next(c for c in app.components if c.name == "Locomotion")
        assert base.properties == {p.name: p.default for p in loco.properties}
        assert [type(v) for v in base.properties.values()] == [
            type(p.default) for p in loco.properties
        ]
        lines = doc_lines(base.__doc__)
        assert lines[: len(doc_lines(TEXT))] == doc_lines(TEXT)
        assert doc_lines(TEXT) == doc_lines(base.move.__doc__)[: len(doc_lines(TEXT))]
        assert list(inspect.signature(base.move).parameters) == ["self", "args", "kwargs"]
        with pytest.raises(OperationNotImplementedError):
            base.move(None, 1.0)
        telemetry = pkg.MONITORS["Telemetry"].__bases__[0]
        assert contains(doc_lines(telemetry.__doc__), doc_lines(TEXT))  # documentation
        assert telemetry.attribute_defaults["note"] == TEXT
        assert TEXT.splitlines()[0] in telemetry.__doc__  # the xpath, in its description
        module = __import__(f"{package}.UserSide", fromlist=["CONTAINER"])
        assert module.CONTAINER == "UserSide" and module.LAUNCHER.package == package
        assert contains(doc_lines(module.__doc__), doc_lines(TEXT))
        assert 'on host h"o\\st' in module.__doc__  # the host, escaped in the docstring


@pytest.mark.parametrize(
    ("where", "name", "why"),
    [
        ("component", "class", "a Python keyword"),
        ("component", "None", "a Python keyword"),
        ("component", "a-b", "not an identifier"),
        ("operation", "get", "a name of the component API"),
        ("operation", "_hidden", "it starts with _"),
        ("operation", "model_types", "a name the generated base class uses"),
        ("operation", "unimplemented", "a name the generated base class uses"),
        ("container", "model_types", "a module of the generated package"),
        ("parameter", "self", "parameter 'self'"),
        ("parameter", "lambda", "a Python keyword"),
        ("container", "registry", "a module of the generated package"),
        ("container", "Base", "a module of the generated package"),
        ("monitor", "def", "a Python keyword"),
        ("monitor", "x y", "not an identifier"),
        ("component", "__init__", "base/__init__.py and components/__init__.py"),
        ("monitor", "__init__", "base/__init__.py and monitors/__init__.py"),
        ("operation", "PortSpec", "a name the generated base class uses"),
        ("container", "model_types", "a module of the generated package"),
    ],
)
def test_names_that_cannot_be_python_are_refused(tmp_path: Path, weblab, where, name, why):
    app = weblab
    loco = next(c for c in app.components if c.name == "Locomotion")
    if where == "component":
        changed = r(loco, name=name)
    elif where == "operation":
        changed = r(loco, operations=(r(loco.operations[0], name=name),))
    elif where == "parameter":
        op = loco.operations[0]
        changed = r(loco, operations=(r(op, parameters=(r(op.parameters[0], name=name),)),))
    if where == "container":
        app = r(app, containers=(r(app.containers[0], name=name), *app.containers[1:]))
    elif where == "monitor":
        app = r(app, monitors=(r(app.monitors[0], name=name), *app.monitors[1:]))
    else:
        app = r(app, components=tuple(changed if c is loco else c for c in app.components))
    ctx = context(app, tmp_path, target="python")
    with pytest.raises(BuildError) as caught:
        python(ctx)
    (diagnostic,) = caught.value.diagnostics
    assert diagnostic.code == "G703"
    assert repr(name) in diagnostic.message and why.split(" (")[0] in diagnostic.message
    assert "cannot be written into a Python file" in diagnostic.message
    assert not ctx.files
