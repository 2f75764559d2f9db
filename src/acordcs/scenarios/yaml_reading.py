"""A scenario file read as YAML into values that know where they were written (file:line:col).

PyYAML's event stream is checked first: anchors, aliases and explicit tags are refused (no alias
bombs, no constructor of any kind runs), and so are files over :data:`MAX_BYTES`, documents
nested deeper than :data:`MAX_DEPTH` and more than :data:`MAX_NODES` values. Then its composer's
nodes carry their marks into :class:`Located` values; scalars are typed by YAML's safe resolver
(numbers, booleans, null, strings) and nothing else.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

from acordcs.diagnostics import Diagnostic, diagnostic

MAX_BYTES = 1 << 20  # 1 MiB: a scenario file is written by hand, or a short trace
MAX_DEPTH = 32
MAX_NODES = 200_000


class ScenarioFileError(Exception):
    """A scenario file that cannot be used: its diagnostic (file:line:col)."""

    def __init__(self, found: Diagnostic) -> None:
        super().__init__(found.format_text())
        self.diagnostic = found


@dataclass(frozen=True, slots=True)
class Located:
    """A value of the file (dict of str -> Located, list of Located, or a scalar) and where it
    was written: 1-based ``line`` and ``column``; ``key`` is where its key was, in a mapping."""

    value: Any
    file: str
    line: int
    column: int

    def where(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"

    def fail(self, code: str, message: str) -> ScenarioFileError:
        """The error to raise about this value."""
        return ScenarioFileError(
            diagnostic(code, message, file=self.file, line=self.line, column=self.column)
        )


def read_scenario_yaml(path: str) -> Located:
    """The file at ``path`` as a :class:`Located` tree. Raises ScenarioFileError (S801: cannot be
    read or too large; S802: not YAML this reader takes)."""
    import yaml  # only this command reads YAML

    try:
        size = os.stat(path).st_size
        if size > MAX_BYTES:
            raise _error(
                "S801",
                f"scenario file is {size} bytes, more than the {MAX_BYTES} this reader takes; "
                "split it into several files",
                path,
            )
        with open(path, "rb") as handle:
            data = handle.read(MAX_BYTES + 1)
    except OSError as exc:
        raise _error(
            "S801", f"cannot read the scenario file: {exc.strerror or exc}", path
        ) from None
    if len(data) > MAX_BYTES:
        raise _error("S801", f"scenario file is more than {MAX_BYTES} bytes", path)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise _error(
            "S801", f"scenario file is not UTF-8 (byte {exc.start}); save it as UTF-8", path
        ) from None
    try:
        _check_events(yaml, text, path)
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, column = (mark.line + 1, mark.column + 1) if mark else (0, 0)
        raise _error(
            "S802", f"not valid YAML: {exc.problem or exc.context}", path, line, column
        ) from None
    except yaml.YAMLError as exc:
        raise _error("S802", f"not valid YAML: {exc}", path) from None
    if root is None:
        raise _error("S803", "the scenario file is empty; give a list under 'scenarios:'", path)
    return _located(yaml, root, path)


def _check_events(yaml: Any, text: str, path: str) -> None:
    depth = nodes = 0
    for event in yaml.parse(text, Loader=yaml.SafeLoader):
        mark = event.start_mark
        at = (mark.line + 1, mark.column + 1)
        if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None):
            raise _error(
                "S802",
                "YAML anchors and aliases (&name, *name) are refused in scenario files; "
                "write the values out",
                path,
                *at,
            )
        if getattr(event, "tag", None) is not None and not isinstance(
            event, yaml.DocumentStartEvent
        ):
            raise _error(
                "S802",
                f"YAML tags ({event.tag}) are refused in scenario files; write plain values",
                path,
                *at,
            )
        if isinstance(event, yaml.DocumentStartEvent) and nodes:
            raise _error("S802", "one YAML document per scenario file (a second '---')", path, *at)
        if isinstance(event, yaml.CollectionStartEvent):
            depth += 1
            if depth > MAX_DEPTH:
                raise _error("S806", f"nested deeper than {MAX_DEPTH} levels", path, *at)
        elif isinstance(event, yaml.CollectionEndEvent):
            depth -= 1
        if isinstance(event, yaml.NodeEvent):
            nodes += 1
            if nodes > MAX_NODES:
                raise _error("S806", f"more than {MAX_NODES} values in one file", path, *at)


def _located(yaml: Any, node: Any, path: str) -> Located:
    line, column = node.start_mark.line + 1, node.start_mark.column + 1
    if isinstance(node, yaml.MappingNode):
        out: dict[str, Located] = {}
        keys: dict[str, Located] = {}
        for key_node, value_node in node.value:
            key = _located(yaml, key_node, path)
            if not isinstance(key.value, str):
                raise key.fail("S803", f"a key must be a name, not {key.value!r}")
            if key.value in out:
                raise key.fail(
                    "S803", f"key {key.value!r} given twice (first at line {keys[key.value].line})"
                )
            keys[key.value] = key
            out[key.value] = _located(yaml, value_node, path)
        return Located(Keyed(out, keys), path, line, column)
    if isinstance(node, yaml.SequenceNode):
        return Located([_located(yaml, n, path) for n in node.value], path, line, column)
    # A scalar as the safe resolver typed it (int, float, bool, null, else str): nothing more.
    value: Any = node.value
    if node.tag.rsplit(":", 1)[-1] in ("int", "float", "bool", "null"):
        value = _scalars(yaml).construct_object(node)
    return Located(value, path, line, column)


_constructor: list[Any] = []


def _scalars(yaml: Any) -> Any:
    """One SafeLoader, made once, whose constructor types the scalars."""
    if not _constructor:
        _constructor.append(yaml.SafeLoader(""))
    return _constructor[0]


class Keyed(dict):
    """A mapping's values by key, and where each key was written (:attr:`keys`)."""

    def __init__(self, values: dict[str, Located], keys: dict[str, Located]) -> None:
        super().__init__(values)
        self.keys_at = keys


def _error(code: str, message: str, path: str, line: int = 0, column: int = 0) -> ScenarioFileError:
    return ScenarioFileError(diagnostic(code, message, file=path, line=line, column=column))
