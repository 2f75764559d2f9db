"""Drift between the model and the Java classes of the components tagged ``language=java``
(``java/<package>/<C>.java``, written once by the ``java`` target, then the user's): a method of
an operation the model renamed or removed since the previous build, told apart by the
operation's id in the previous descriptor, as :mod:`acordcs.generator.drift` does for the Python
classes (warning G704 at the method's line). Such a method overrides nothing any more, and the
operation's new method has no code: javac refuses the class, and says so in its own words; the
warning says what the model did and what to rename.

The methods are found in the source with its comments and literals blanked (lines kept): a
declaration is a name followed by ``(`` after a type, at the start of a line of the class's
body; what else the source holds is javac's to judge.
"""

from __future__ import annotations

import re
from pathlib import Path

from acordcs.descriptor import Application, Component
from acordcs.generator.drift import Drift, stale_operations
from acordcs.generator.paths import read_bounded
from acordcs.java_names import identifier, method, package

_BLANKED = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
_DECLARATION = re.compile(
    r"^[ \t]*(?:@[\w.]+[ \t]+)*(?:(?:public|protected|private|static|final|synchronized|"
    r"abstract|native|strictfp)[ \t]+)*[\w.$<>\[\]?, ]*[\w$>\]][ \t]+(?P<name>[\w$]+)[ \t]*\(",
    re.M,
)


def java_methods(source: str) -> dict[str, int]:
    """The methods declared in Java ``source``: name -> the line of its first declaration."""
    blanked = _BLANKED.sub(lambda m: re.sub(r"[^\n]", " ", m.group()), source)
    found: dict[str, int] = {}
    for match in _DECLARATION.finditer(blanked):
        name = match["name"]
        if name not in ("new", "return", "throw", "else") and name not in found:
            found[name] = blanked.count("\n", 0, match.start("name")) + 1
    return found


def find_java_drift(out: Path, old: Application | None, new: Application) -> list[Drift]:
    """Every method of a Java component's class that implemented an operation the model renamed
    or removed since ``old`` (None: no previous build, nothing to compare)."""
    if old is None:
        return []
    before = {c.id: c for c in old.components}
    found: list[Drift] = []
    for component in new.components:
        previous = before.get(component.id)
        if component.language != "java" or previous is None:
            continue
        path = f"java/{package(new.name)}/{identifier(component.name)}.java"
        try:
            source = read_bounded(out / path).decode("utf-8")
        except (OSError, UnicodeDecodeError):
            continue  # missing: written again; unreadable: javac says so
        found += _stale(path, java_methods(source), previous, component)
    return found


def _stale(path: str, methods: dict[str, int], old: Component, new: Component) -> list[Drift]:
    out = []
    cls = identifier(new.name)
    for old_op, name, line, now in stale_operations(methods, old, new, method):
        if now is not None:
            message = (
                f"method {name}() of Java class {cls} implements operation {old_op.name}, which "
                f"the model now names {now} (id {old_op.id}): rename the method to {now}; until "
                f"then it overrides nothing, {now}() has no code and javac refuses the class"
            )
        else:
            message = (
                f"method {name}() of Java class {cls} implements operation {old_op.name} (id "
                f"{old_op.id}), which is no longer in the model: remove the method (with its "
                "@Override javac refuses the class), or put the operation back in the model"
            )
        out.append(Drift(path, line, message, new.qualified_name, old_op.id))
    return out
