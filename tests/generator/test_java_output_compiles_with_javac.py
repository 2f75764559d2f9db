"""What the ``java`` target writes compiles with javac: both samples, and models whose strings
and names are hostile (comment ends, quotes, backslashes, Unicode escapes, line breaks, non-ASCII,
keywords), which still compile to exactly the classes the model names, with no code of the
model's making: every model string is inside a string literal or a comment.

Needs a JDK (javac). Outside CI (``CI`` is not ``true``) the tests skip without it; in CI they
fail (``make test`` installs openjdk-17-jdk-headless through scripts/system-packages.sh).
"""

from __future__ import annotations

import dataclasses
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from acordcs.descriptor import Application
from acordcs.generator.targets import targets
from tests.support.generator import build, context
from tests.support.toolchain import SMARTROOM, WEBLAB

pytestmark = pytest.mark.service
r = dataclasses.replace


def javac() -> str:
    found = shutil.which("javac")
    if found is None:
        reason = "javac is not on PATH (install openjdk-17-jdk-headless)"
        if os.environ.get("CI") == "true":
            pytest.fail(f"the Java compile tests cannot run in CI: {reason}")
        pytest.skip(f"the Java compile tests need a JDK: {reason}")
    return found


def compile_tree(sources: Path, classes: Path) -> set[str]:
    """Compile every .java under ``sources``; the classes made, as dotted names."""
    files = sorted(str(p) for p in sources.rglob("*.java"))
    assert files
    done = subprocess.run(
        [javac(), "-Xlint:all", "-encoding", "US-ASCII", "-d", str(classes), *files],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return {
        p.relative_to(classes).with_suffix("").as_posix().replace("/", ".")
        for p in classes.rglob("*.class")
    }


API = {
    "org.acordcs.runtime.CtxComponent",
    "org.acordcs.runtime.CtxComponent$Host",
    "org.acordcs.runtime.Port",
    "org.acordcs.runtime.Port$Link",
    "org.acordcs.runtime.Port$Kind",
    "org.acordcs.runtime.Port$Role",
    "org.acordcs.runtime.RuleEngine",
}


@pytest.mark.parametrize(("model", "package"), [(WEBLAB, "weblab"), (SMARTROOM, "smartroom")])
def test_both_samples_compile(tmp_path: Path, model: Path, package: str, request):
    result = build(model, tmp_path / "out", "-t", "java")
    assert result.code == 0, result.both
    made = compile_tree(tmp_path / "out" / "java", tmp_path / "classes")
    app = request.getfixturevalue(package)
    expected = {f"{package}.{c.name}{s}" for c in app.components for s in ("", "Base")}
    assert made == API | expected


# ------------------------------------------------------------------------- hostile strings
HOSTILE = (
    '*/ class Injected {} /* "quoted" \\ back\\slash \\u002a/ \\u000a class Unicode {} '
    "\u00e9t\u00e9 \u2028 \U0001f600 \x7f \t tab @param <b>&amp;</b> **/"
)
CODE = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"', re.S)


def code_only(text: str) -> str:
    """``text`` without its comments and string literals."""
    return CODE.sub(" ", text)


def hostile(app: Application) -> Application:
    components = []
    for n, c in enumerate(app.components):
        props = tuple(
            r(p, default=HOSTILE + "\n\r\nline", documentation=HOSTILE + "\nsecond line")
            if p.kind == "string"
            else r(p, documentation=HOSTILE)
            for p in c.properties
        )
        ops = tuple(r(o, documentation="\r\n".join([HOSTILE] * 2)) for o in c.operations)
        ports = tuple(r(p, documentation=HOSTILE) for p in c.ports)
        components.append(
            r(
                c,
                name=c.name if n else "Access\u00e9-2",  # not an identifier: made one
                qualified_name=c.qualified_name + HOSTILE,
                documentation=HOSTILE + "\n" + HOSTILE,
                properties=props,
                operations=ops,
                ports=ports,
            )
        )
    return r(app, name="Class", components=tuple(components))


def run_java(app: Application, tmp_path: Path) -> Path:
    made = context(app, tmp_path, target="java", source="m */ \\u000a.xmi")
    targets()["java"].run(made)
    out = tmp_path / "out"
    for f in made.files:
        (out / f.path).parent.mkdir(parents=True, exist_ok=True)
        (out / f.path).write_bytes(f.data)
    return out


def test_hostile_strings_compile_to_the_model_classes_only(tmp_path: Path, weblab):
    app = hostile(weblab)
    out = run_java(app, tmp_path)
    package = out / "java" / "class_"
    names = sorted(p.name for p in package.iterdir())
    assert "Access__2.java" in names and "Access__2Base.java" in names
    for path in (out / "java").rglob("*.java"):
        text = path.read_bytes().decode("ascii")  # every file is ASCII
        rest = code_only(text)
        for word in ("Injected", "Unicode", "quoted", "\\u", "tab", "line"):
            assert word not in rest, (path, word)
    made = compile_tree(out / "java", tmp_path / "classes")
    expected = {
        f"class_.{n}{s}"
        for n in ["Access__2", *(c.name for c in app.components[1:])]
        for s in ("", "Base")
    }
    assert made == API | expected
    text = (package / "PanoramicCameraBase.java").read_text(encoding="ascii")
    literal = next(
        line for line in text.splitlines() if "protected java.lang.String resolution" in line
    )
    assert '\\"quoted\\" \\\\ back\\\\slash \\\\u002a/ \\\\u000a' in literal
    assert "\\u00e9t\\u00e9 \\u2028 \\ud83d\\ude00 \\177 \\t tab" in literal
    assert literal.endswith('\\n\\r\\nline";')
    assert "*&#47; class Injected" in text and "&#92;u000a" in text


def test_a_hostile_default_is_a_string_constant_of_the_class(tmp_path: Path, weblab):
    """What looks like code in a string default is a constant of the compiled class (javap)."""
    out = run_java(hostile(weblab), tmp_path)
    classes = tmp_path / "classes"
    compile_tree(out / "java", classes)
    javap = shutil.which("javap")
    if javap is None:
        pytest.skip("javap is not on PATH")
    done = subprocess.run(
        [javap, "-c", "-constants", "-cp", str(classes), "class_.PanoramicCameraBase"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "class Injected {}" in done.stdout  # inside the constant, as data


def test_components_named_like_java_types_compile(tmp_path: Path, weblab):
    """Generated code names every type fully qualified, and suffixes ``java`` and ``org``: a
    component named Object, String, Port, CtxComponent, java or Override changes nothing."""
    names = ("Object", "String", "Port", "CtxComponent", "java", "Override")
    components = tuple(r(c, name=n) for c, n in zip(weblab.components, names, strict=True))
    out = run_java(r(weblab, name="org", components=components), tmp_path)
    made = compile_tree(out / "java", tmp_path / "classes")
    classes = ("Object", "String", "Port", "CtxComponent", "java_", "Override")
    assert made == API | {f"org_.{n}{s}" for n in classes for s in ("", "Base")}
