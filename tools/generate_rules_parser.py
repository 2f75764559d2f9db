"""Generate the rule language's parser, ``src/acordcs/rules/standalone_parser.py``, from
``src/acordcs/rules/rules.lark`` with lark's standalone generator (``python -m
lark.tools.standalone``, its public command line).

The generated module holds lark's LALR(1) parser and contextual lexer and the grammar's tables as
plain data: running it needs no lark, and no lark release can change what it does until it is
generated again. Its code is under the Mozilla Public License 2.0 (its header says so; the text is
``LICENSES/MPL-2.0.txt``). lark numbers the parser's states differently from one run to the next,
so a new run differs in its tables' numbering only; ``tests/rules/test_generated_parser_is_current.py``
compares what the tables mean, and fails when the grammar changed since the module was generated.

Run from the repository: ``.venv/bin/python tools/generate_rules_parser.py`` (``--check``: write
nothing, exit 1 when the module is not current).
"""

from __future__ import annotations

import ast
import hashlib
import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

RULES = Path(__file__).resolve().parents[1] / "src" / "acordcs" / "rules"
GRAMMAR = RULES / "rules.lark"
MODULE = RULES / "standalone_parser.py"
STARTS = ("start_fuzzy", "start_crisp", "start_terms")
# lark's options as the parser needs them: LALR(1) with the contextual lexer (lark's default for
# lalr), [optional] items as None placeholders.
OPTIONS = ("--maybe_placeholders",)


def grammar_digest(grammar: str) -> str:
    return hashlib.sha256(grammar.encode("utf-8")).hexdigest()


def recorded_digest(module_text: str) -> str | None:
    """The sha256 of the grammar a generated module was made from, as its header records it."""
    found = re.search(r"^# rules\.lark sha256: ([0-9a-f]{64})$", module_text[:1000], re.M)
    return found.group(1) if found else None


def recorded_lark_version(module_text: str) -> str | None:
    found = re.search(r"^__version__ = \"([^\"]+)\"$", module_text[:2000], re.M)
    return found.group(1) if found else None


def header(grammar: str, lark_version: str) -> str:
    return (
        "# Generated from rules.lark by tools/generate_rules_parser.py with lark's standalone\n"
        f"# generator, lark {lark_version}; do not edit: run that script again.\n"
        f"# rules.lark sha256: {grammar_digest(grammar)}\n"
        "# mypy: ignore-errors\n"
        "# ruff: noqa\n"
    )


def generate(grammar_path: Path = GRAMMAR) -> str:
    """The module's text for the grammar at ``grammar_path``."""
    import lark

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp, "standalone_parser.py")
        command = [sys.executable, "-m", "lark.tools.standalone"]
        for start in STARTS:
            command += ["-s", start]
        command += [*OPTIONS, "-o", str(out), str(grammar_path)]
        subprocess.run(command, check=True, capture_output=True, text=True)
        body = out.read_text(encoding="utf-8")
    return header(grammar_path.read_text(encoding="utf-8"), lark.__version__) + body


def _literal(text: str, name: str) -> object:
    found = re.search(rf"^{name} = \(\n(.*?)\n\)$", text, re.M | re.S)
    if found is None:
        raise ValueError(f"no {name} in the module: not what lark's standalone generator writes")
    return ast.literal_eval(found.group(1))


def tables(text: str) -> dict[str, object]:
    """What the tables of a generated module mean, whatever lark numbered its states: the states
    numbered in the order a walk from the start states (by name) through the shifts (by symbol
    name) meets them, each with its actions by symbol name (a reduction by its rule); the
    terminals, the rules and the options."""
    data, memo = _literal(text, "DATA"), _literal(text, "MEMO")
    parser = data["parser"]["parser"]
    names, states = parser["tokens"], parser["states"]
    number: dict[int, int] = {}
    for start in sorted(parser["start_states"]):
        number.setdefault(parser["start_states"][start], len(number))
    walked = list(number)
    for state in walked:
        for _symbol, (action, target) in sorted(states[state].items(), key=lambda a: names[a[0]]):
            if action == 0 and target not in number:  # 0: shift
                number[target] = len(number)
                walked.append(target)

    def rule(reference: dict) -> str:
        return json.dumps(memo[reference["@"]], sort_keys=True)

    return {
        "states": [
            sorted(
                (
                    names[symbol],
                    ("shift", number[target]) if action == 0 else ("reduce", rule(target)),
                )
                for symbol, (action, target) in states[state].items()
            )
            for state in walked
        ],
        "unreached states": len(states) - len(walked),
        "starts": {name: number[s] for name, s in parser["start_states"].items()},
        "ends": {name: number.get(s) for name, s in parser["end_states"].items()},
        "terminals": sorted(rule(t) for t in data["parser"]["lexer_conf"]["terminals"]),
        "rules": sorted(rule(r) for r in data["rules"]),
        "options": data["options"],
    }


def code(text: str) -> str:
    """The module without its header and its tables: lark's parser as the generator wrote it."""
    return text[
        text.index("# The file was automatically generated by Lark") : text.index("DATA = (")
    ]


def main(argv: list[str]) -> int:
    text = generate()
    if "--check" in argv:
        current = MODULE.read_text(encoding="utf-8") if MODULE.is_file() else ""
        if (
            recorded_digest(current) != grammar_digest(GRAMMAR.read_text(encoding="utf-8"))
            or tables(current) != tables(text)
            or code(current) != code(text)
        ):
            print(f"{MODULE}: not current; run python tools/generate_rules_parser.py")
            return 1
        print(f"{MODULE}: current")
        return 0
    MODULE.write_text(text, encoding="utf-8")
    print(f"wrote {MODULE}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
