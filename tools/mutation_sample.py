"""Mutation scores of modules against their own tests, from a seeded sample of mutants.

A mutant is the module with one change a test should notice: an arithmetic or bitwise operator
swapped (``+`` -> ``-``, ``*`` -> ``/``, ``|`` -> ``&``, also in ``+=``), a comparison moved by its
boundary or negated (``<`` -> ``<=``, ``==`` -> ``!=``, ``in`` -> ``not in``, ``is`` -> ``is not``),
``and`` <-> ``or``, a ``not`` or a unary minus dropped, a number constant plus one, ``True`` <->
``False``, a returned value replaced by ``None``. Type annotations and strings are left alone.

The module's mutants are listed in a fixed order, ``--sample`` of them drawn with ``--seed``
(all of them when there are fewer), and each is run against the module's own test files
(``pytest -x -q``, ``--timeout`` seconds at most) in a temporary copy of the repository, so the
working tree is never left mutated. The mutated module is written with ``ast.unparse``: the
unmutated module written so must pass its tests first, or nothing is measured. A mutant is
*killed* when the tests fail, *survived* when they pass, *timeout* when they run out of time;
the score is (killed + timeout) / mutants. Run it from the repository's root (it is slow: not
part of ``make test``)::

    nice -n 10 .venv/bin/python -m tools.mutation_sample            # the four modules of MODULES
    .venv/bin/python -m tools.mutation_sample --list src/acordcs/rules/binding.py
    .venv/bin/python -m tools.mutation_sample --only 3,17 src/acordcs/rules/binding.py

Tests only added kill every mutant the tests before them killed, so after adding tests the
survivors of a run (``--only``) are all that can change.
"""

from __future__ import annotations

import argparse
import ast
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

MODULES: dict[str, tuple[str, ...]] = {
    "src/acordcs/runtime/context/xpathcost.py": (
        "tests/runtime/test_context_xpath_cost.py",
        "tests/runtime/test_context_xpath_cost_model_is_pinned.py",
        "tests/runtime/test_context_xpath_cost_knows_which_node_sets_hold_one_node.py",
    ),
    "src/acordcs/engines/fuzzy/membership.py": (
        "tests/engines/test_fuzzy_membership.py",
        "tests/engines/test_membership_limits_and_extents_are_exact.py",
    ),
    "src/acordcs/generator/manifest.py": (
        "tests/generator/test_manifests_of_older_versions_read_back.py",
        "tests/generator/test_manifest_is_the_json_of_its_data.py",
    ),
    "src/acordcs/rules/binding.py": (
        "tests/rules/test_rule_names_bind_in_scope.py",
        "tests/rules/test_crisp_writes_and_call_arguments_are_inputs.py",
    ),
}
"""Each measured module and its own test files (paths from the repository's root)."""

SEED = 36
SAMPLE = 150
PYTEST_ARGS = ("-x", "-q", "-p", "no:cacheprovider", "--hypothesis-profile=ci")

_OPERATORS: dict[type, type] = {
    ast.Add: ast.Sub,
    ast.Sub: ast.Add,
    ast.Mult: ast.Div,
    ast.Div: ast.Mult,
    ast.FloorDiv: ast.Div,
    ast.Mod: ast.FloorDiv,
    ast.Pow: ast.Mult,
    ast.BitOr: ast.BitAnd,
    ast.BitAnd: ast.BitOr,
    ast.BitXor: ast.BitOr,
    ast.LShift: ast.RShift,
    ast.RShift: ast.LShift,
}
_COMPARISONS: dict[type, type] = {
    ast.Lt: ast.LtE,
    ast.LtE: ast.Lt,
    ast.Gt: ast.GtE,
    ast.GtE: ast.Gt,
    ast.Eq: ast.NotEq,
    ast.NotEq: ast.Eq,
    ast.In: ast.NotIn,
    ast.NotIn: ast.In,
    ast.Is: ast.IsNot,
    ast.IsNot: ast.Is,
}
_SYMBOLS: dict[type, str] = {
    ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//", ast.Mod: "%",
    ast.Pow: "**", ast.BitOr: "|", ast.BitAnd: "&", ast.BitXor: "^", ast.LShift: "<<",
    ast.RShift: ">>", ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==",
    ast.NotEq: "!=", ast.In: "in", ast.NotIn: "not in", ast.Is: "is", ast.IsNot: "is not",
}  # fmt: skip
_NOT_CODE = frozenset(("annotation", "returns"))  # type annotations: not evaluated here


@dataclass(frozen=True)
class Mutant:
    """The ``number``-th change of a module (in the order :func:`mutants` lists them)."""

    number: int
    line: int
    change: str


class _Mutator(ast.NodeTransformer):
    """Walks a module's code in a fixed order, numbering every possible change; applies the
    ``target``-th one (none when ``target`` is None, only listing them)."""

    def __init__(self, target: int | None = None) -> None:
        self.target = target
        self.found: list[Mutant] = []

    def generic_visit(self, node: ast.AST) -> ast.AST:
        for name, value in ast.iter_fields(node):
            if name in _NOT_CODE:
                continue
            if isinstance(value, list):
                new = [self.visit(v) if isinstance(v, ast.AST) else v for v in value]
                value[:] = [v for v in new if v is not None]
            elif isinstance(value, ast.AST):
                setattr(node, name, self.visit(value))
        return node

    def visit_ImportFrom(self, node: ast.ImportFrom) -> ast.AST:
        return node  # nothing to mutate (a level is not a number of the code)

    def visit(self, node: ast.AST) -> ast.AST:
        for change, apply in self._changes(node):
            number = len(self.found)
            self.found.append(Mutant(number, getattr(node, "lineno", 0), change))
            if number == self.target:
                return apply()
        return self.generic_visit(node)

    def _changes(self, node: ast.AST) -> Iterator[tuple[str, Callable[[], ast.AST]]]:
        if isinstance(node, ast.BinOp | ast.AugAssign) and type(node.op) in _OPERATORS:
            new = _OPERATORS[type(node.op)]
            yield _swap(node.op, new), lambda: _set(node, "op", new())
        elif isinstance(node, ast.Compare):
            for i, op in enumerate(node.ops):
                new = _COMPARISONS[type(op)]
                yield _swap(op, new), partial(_set_op, node, i, new())
        elif isinstance(node, ast.BoolOp):
            new = ast.Or if isinstance(node.op, ast.And) else ast.And
            yield _swap_words(node.op, new), lambda: _set(node, "op", new())
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not | ast.USub):
            word = "not" if isinstance(node.op, ast.Not) else "-"
            yield f"{word!r} dropped", lambda: node.operand
        elif isinstance(node, ast.Constant) and isinstance(node.value, bool):
            yield f"{node.value} -> {not node.value}", lambda: _set(node, "value", not node.value)
        elif isinstance(node, ast.Constant) and isinstance(node.value, int | float):
            new_value = node.value + 1
            yield f"{node.value!r} -> {new_value!r}", lambda: _set(node, "value", new_value)
        elif isinstance(node, ast.Return) and not _is_none(node.value):
            yield "return None", lambda: _set(node, "value", ast.Constant(None))


def _is_none(node: ast.AST | None) -> bool:
    return node is None or (isinstance(node, ast.Constant) and node.value is None)


def _set(node: ast.AST, name: str, value: object) -> ast.AST:
    setattr(node, name, value)
    return node


def _set_op(node: ast.Compare, index: int, op: ast.cmpop) -> ast.AST:
    node.ops[index] = op
    return node


def _swap(old: ast.AST, new: type) -> str:
    return f"{_SYMBOLS[type(old)]!r} -> {_SYMBOLS[new]!r}"


def _swap_words(old: ast.AST, new: type) -> str:
    return f"{type(old).__name__.lower()!r} -> {new.__name__.lower()!r}"


def mutants(source: str) -> list[Mutant]:
    """Every mutant of ``source``, numbered in a fixed order."""
    mutator = _Mutator()
    mutator.visit(ast.parse(source))
    return mutator.found


def mutated(source: str, mutant: Mutant | None) -> str:
    """``source`` with ``mutant``'s change, as ``ast.unparse`` writes it (None: no change)."""
    tree = _Mutator(None if mutant is None else mutant.number).visit(ast.parse(source))
    return ast.unparse(ast.fix_missing_locations(tree)) + "\n"


def sample(found: Sequence[Mutant], size: int, seed: int) -> list[Mutant]:
    """``size`` of ``found`` drawn with ``seed`` (all when there are fewer), in their order."""
    if len(found) <= size:
        return list(found)
    return sorted(random.Random(seed).sample(list(found), size), key=lambda m: m.number)


@dataclass
class Result:
    module: str
    total: int
    outcomes: dict[Mutant, str] = field(default_factory=dict)  # killed, survived, timeout

    def count(self, outcome: str) -> int:
        return sum(1 for o in self.outcomes.values() if o == outcome)

    @property
    def score(self) -> float:
        return (self.count("killed") + self.count("timeout")) / max(1, len(self.outcomes))


def _files(root: Path) -> list[Path]:
    """The repository's files (tracked and new, not ignored); every file outside a git tree."""
    try:
        listed = subprocess.run(
            ["git", "ls-files", "-co", "--exclude-standard", "-z"],
            cwd=root, capture_output=True, check=True,
        ).stdout  # fmt: skip
        return [Path(p) for p in listed.decode().split("\0") if p and (root / p).is_file()]
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", ".venv", "__pycache__"}
        return [
            p.relative_to(root)
            for p in root.rglob("*")
            if p.is_file() and not skip & set(p.relative_to(root).parts)
        ]


def _copy(root: Path, into: Path) -> None:
    for rel in _files(root):
        (into / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(root / rel, into / rel)


def _pytest(copy: Path, tests: Sequence[str], args: Sequence[str], timeout: float) -> str:
    """Run the tests in ``copy``: killed, survived or timeout."""
    env = dict(os.environ, PYTHONPATH=str(copy / "src"))
    with subprocess.Popen(
        [sys.executable, "-m", "pytest", *args, *tests],
        cwd=copy, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        start_new_session=True,  # its children (a build's Saxon) are stopped with it
    ) as process:  # fmt: skip
        try:
            return "survived" if process.wait(timeout) == 0 else "killed"
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            return "timeout"


def measure(
    root: Path,
    module: str,
    tests: Sequence[str],
    *,
    size: int = SAMPLE,
    seed: int = SEED,
    timeout: float | None = None,
    pytest_args: Sequence[str] = PYTEST_ARGS,
    only: frozenset[int] | None = None,
) -> Result:
    """Run a seeded sample of ``module``'s mutants against ``tests`` in a copy of ``root``.
    ``timeout``: seconds per mutant (None: four times the unmutated run, at least 20); ``only``:
    the numbers of the sampled mutants to run (None: all of them)."""
    source = (root / module).read_text(encoding="utf-8")
    found = mutants(source)
    result = Result(module, len(found))
    with tempfile.TemporaryDirectory(prefix="mutation-") as tmp:
        copy = Path(tmp)
        _copy(root, copy)
        target = copy / module
        target.write_text(mutated(source, None), encoding="utf-8")
        started = time.monotonic()
        if _pytest(copy, tests, pytest_args, 600) != "survived":
            raise SystemExit(f"{module}: its tests fail on the unmutated module; nothing measured")
        limit = timeout or max(20.0, 4 * (time.monotonic() - started))
        stamp = int(time.time()) - 10**6  # a distinct mtime per mutant: no stale bytecode
        for mutant in sample(found, size, seed):
            if only is not None and mutant.number not in only:
                continue
            target.write_text(mutated(source, mutant), encoding="utf-8")
            os.utime(target, (stamp + mutant.number, stamp + mutant.number))
            result.outcomes[mutant] = _pytest(copy, tests, pytest_args, limit)
    return result


def report(results: Sequence[Result]) -> str:
    """The table of scores, then every survivor with its line."""
    head = (
        f"{'module':<44} {'mutants':>11} {'killed':>6} {'survived':>8} {'timeout':>7} {'score':>6}"
    )
    lines = [head]
    for r in results:
        drawn = f"{len(r.outcomes)} of {r.total}"
        lines.append(
            f"{r.module:<44} {drawn:>11} {r.count('killed'):>6} {r.count('survived'):>8} "
            f"{r.count('timeout'):>7} {r.score:>6.0%}"
        )
    for r in results:
        survivors = [m for m, o in r.outcomes.items() if o == "survived"]
        if survivors:
            lines.append(f"\nsurvivors in {r.module}:")
            lines += [f"  line {m.line:>4}  {m.change}  (mutant {m.number})" for m in survivors]
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.mutation_sample", description=__doc__)
    parser.add_argument("modules", nargs="*", help="modules of MODULES (default: all of them)")
    parser.add_argument("--sample", type=int, default=SAMPLE, help="mutants per module")
    parser.add_argument("--seed", type=int, default=SEED, help="seed of the sample")
    parser.add_argument("--timeout", type=float, help="seconds per mutant")
    parser.add_argument("--list", action="store_true", help="list the mutants, run nothing")
    parser.add_argument(
        "--only",
        type=lambda text: frozenset(int(n) for n in text.split(",")),
        help="run only these sampled mutants (numbers, comma-separated: a run's survivors again)",
    )
    args = parser.parse_args(argv)
    root = Path.cwd()
    unknown = [m for m in args.modules if m not in MODULES]
    if unknown:
        parser.error(f"not a module of MODULES: {', '.join(unknown)}")
    chosen = args.modules or list(MODULES)
    if args.list:
        for module in chosen:
            found = mutants((root / module).read_text(encoding="utf-8"))
            drawn = set(sample(found, args.sample, args.seed))
            for m in found:
                print(f"{module}:{m.line}: {m.change}{'  (sampled)' if m in drawn else ''}")
        return 0
    results = []
    for module in chosen:
        results.append(measure(root, module, MODULES[module], size=args.sample,
                               seed=args.seed, timeout=args.timeout, only=args.only))  # fmt: skip
        print(report(results[-1:]), flush=True)
    print("\n" + report(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
