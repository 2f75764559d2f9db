"""FCL (IEC 61131-7) reader and writer, following jFuzzyLogic where the standard leaves room.

:func:`read_fcl` gives one :class:`FuzzyEngine` per FUNCTION_BLOCK (keyed by block name); each
RULEBLOCK becomes a rule set of that engine with its own operators. Conditions are parsed into the
same tree classes as the paper's syntax (``acordcs.rules.parser``), so both run through one
inference code path. :func:`write_fcl` writes an engine back; reading that text gives an engine with
the same variables, terms, operators, rules and results.

Defaults when a block leaves them out (jFuzzyLogic's): AND MIN (OR MAX), ACT MIN, ACCU SUM,
METHOD COG; no DEFAULT keeps the output's last value (like NC). Deviations are listed in
docs/fuzzy-engine.md.
"""

from __future__ import annotations

import gc
import logging
import re
from functools import cache
from importlib import resources
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from acordcs.cachedir import lark_cache
from acordcs.engines.fuzzy import fcl_fast
from acordcs.engines.fuzzy.fcl_errors import syntax_error
from acordcs.engines.fuzzy.fcl_function import parse_function
from acordcs.engines.fuzzy.fcl_writer import format_condition, format_rule, write_fcl
from acordcs.engines.fuzzy.fuzzy_engine import FuzzyEngine
from acordcs.engines.fuzzy.membership import function_membership, make_membership
from acordcs.engines.fuzzy.semantics import (
    ACCU_OPS,
    ACT_OPS,
    AND_OPS,
    FCL_DEFAULTS,
    METHODS,
    OR_OPS,
)
from acordcs.engines.fuzzy.variable import too_many_terms
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import BoolOp, Consequent, Is, Name, Not, Rule, depth_message, names_in
from acordcs.rules.tree import MAX_TERMS, deepest

__all__ = ["format_condition", "format_rule", "read_fcl", "write_fcl"]

log = logging.getLogger("acordcs.engines.fuzzy")

_SHAPES = {
    "trian": "triangle",
    "trape": "trapezoid",
    "gauss": "gaussian",
    "gbell": "bell",
    "sigm": "sigmoid",
}
_UNSUPPORTED = ("singletons", "cosine", "dsigm", "gauss2", "function")


@cache
def _parser() -> Lark:
    grammar = resources.files(__package__).joinpath("fcl.lark").read_text(encoding="utf-8")
    # never cache=True: lark would unpickle a predictable file in the shared temp dir
    return Lark(grammar, parser="lalr", propagate_positions=True, cache=lark_cache(grammar, "fcl"))


def read_fcl(source: str | Path, *, filename: str | None = None) -> dict[str, FuzzyEngine]:
    """Read FCL text (or a file path) into engines, one per FUNCTION_BLOCK, keyed by block name
    (``block<n>`` for an unnamed block). Errors are RuleError with file:line:column."""
    # Reading allocates a few objects per token and makes no reference cycles: the cyclic
    # collector, run every 700 allocations over a growing heap, doubled the time of a 1 MB file.
    paused = gc.isenabled()
    gc.disable()
    try:
        return _read(source, filename)
    finally:
        if paused:
            gc.enable()


def _read(source: str | Path, filename: str | None) -> dict[str, FuzzyEngine]:
    if isinstance(source, Path):
        filename = filename or str(source)
        try:
            source = source.read_text(encoding="utf-8")
        except OSError as exc:
            raise RuleError(f"cannot read FCL file: {exc.strerror}", file=filename) from None
    try:
        tree = fcl_fast.parse(source)
    except fcl_fast.Decline:  # an error, or a rare form: lark reads it (and words the error)
        try:
            tree = _parser().parse(source)
        except UnexpectedInput as err:
            raise syntax_error(err, source, filename) from None
    out: dict[str, FuzzyEngine] = {}
    for n, block in enumerate(tree.children, start=1):
        engine = _Block(block, filename).build()
        key = engine.name or f"block{n}"
        if key in out:
            raise RuleError(
                f"two FUNCTION_BLOCKs are named {key!r}; give each its own name",
                file=filename,
                line=block.meta.line,
                column=block.meta.column,
            )
        out[key] = engine
    return out


class _Block:
    """One FUNCTION_BLOCK: collects declarations, then builds the engine."""

    def __init__(self, tree: Tree, filename: str | None) -> None:
        self.tree, self.file = tree, filename
        self.inputs: dict[str, tuple | None] = {}
        self.outputs: dict[str, tuple | None] = {}
        self.fuzz: dict[str, dict] = {}
        self.declared_at: dict[str, Token] = {}  # variable -> its name in VAR_INPUT/VAR_OUTPUT
        self.blocks: dict[str, Tree] = {}  # variable -> its FUZZIFY or DEFUZZIFY block
        self.spikes: dict[str, Tree] = {}  # variable -> its first singleton or zero-width term
        self.functions: dict[str, Tree] = {}  # variable -> its first FUNCTION term
        self.untermed: set[str] = set()  # inputs without terms or RANGE: not defined

    def error(self, msg: str, tok: Token | Tree | None) -> RuleError:
        line = (
            getattr(tok, "line", None)
            if isinstance(tok, Token)
            else getattr(getattr(tok, "meta", None), "line", None)
        )
        col = (
            getattr(tok, "column", None)
            if isinstance(tok, Token)
            else getattr(getattr(tok, "meta", None), "column", None)
        )
        return RuleError(msg, file=self.file, line=line, column=col)

    def build(self) -> FuzzyEngine:
        kids = self.tree.children
        name = (
            str(kids[1])
            if len(kids) > 1 and isinstance(kids[1], Token) and kids[1].type == "NAME"
            else None
        )
        engine = FuzzyEngine(FCL_DEFAULTS, name=name)
        items = [k for k in kids if isinstance(k, Tree)]
        for item in items:
            if item.data in ("var_input", "var_output"):
                self._declare(item)
        for item in items:
            if item.data in ("fuzzify", "defuzzify"):
                self._terms(item)
        for var in (*self.inputs, *self.outputs):
            self._define(engine, var)
        for item in items:
            if item.data == "ruleblock":
                self._ruleblock(engine, item)
        return engine

    def _declare(self, item: Tree) -> None:
        target = self.inputs if item.data == "var_input" else self.outputs
        for d in item.find_data("var_def"):
            name, vtype = d.children[0], d.children[1]
            if str(vtype).upper() != "REAL":
                raise self.error(
                    f"variable {name!s} has type {vtype!s}; fuzzy variables are REAL", vtype
                )
            if name in self.inputs or name in self.outputs:
                raise self.error(f"variable {name!s} is declared twice", name)
            self.declared_at[str(name)] = name
            target[str(name)] = (
                self._range(d.children[2]) if len(d.children) > 2 and d.children[2] else None
            )

    def _range(self, node: Tree) -> tuple[float, float, Tree]:
        nums = [float(t) for t in node.children if isinstance(t, Token) and t.type == "NUMBER"]
        return nums[0], nums[1], node

    def _terms(self, item: Tree) -> None:
        keyword, var = item.children[0], str(item.children[1])
        declared = self.inputs if item.data == "fuzzify" else self.outputs
        if var not in declared:
            kind = "VAR_INPUT" if item.data == "fuzzify" else "VAR_OUTPUT"
            raise self.error(
                f"{keyword!s} {var}: {var} is not declared in {kind}; declare it there",
                item.children[1],
            )
        info = self.fuzz.setdefault(
            var, {"terms": {}, "range": None, "method": None, "default": None, "nc": False}
        )
        self.blocks.setdefault(var, item)
        for node in item.children[2:]:
            if not isinstance(node, Tree):
                continue
            if node.data == "term":
                tname = str(node.children[1])
                if tname in info["terms"]:
                    raise self.error(f"term {tname} of {var} is defined twice", node.children[1])
                if len(info["terms"]) == MAX_TERMS:  # said at the first one too many: no hang
                    raise self.error(too_many_terms(f"{keyword!s} {var}"), node)
                info["terms"][tname] = self._mf(var, tname, node.children[2])
            elif node.data == "range":
                info["range"] = self._range(node)
            elif node.data == "method":
                value = node.children[1]
                if str(value).upper() not in METHODS:
                    raise self.error(
                        f"unknown METHOD {value!s} for {var}; use one of {', '.join(METHODS)}",
                        value,
                    )
                info["method"] = str(value).upper()
            elif node.data == "default":
                value = node.children[1]
                if value.type == "NUMBER":
                    info["default"] = float(value)
                elif str(value).upper() == "NC":
                    info["nc"] = True
                elif str(value).lower() == "nan":
                    raise self.error(
                        f"DEFAULT := {value!s} is fuzzylite's dialect (no default value); write "
                        "DEFAULT := NC to keep the last value, or a number",
                        value,
                    )
                else:
                    raise self.error(f"DEFAULT must be a number or NC, got {value!s}", value)
            elif node.data == "accu":
                raise self.error(
                    f"ACCU inside DEFUZZIFY {var} is fuzzylite's dialect (its FCL export writes "
                    "ACCU per output); IEC 61131-7 and jFuzzyLogic take it in the RULEBLOCK: move "
                    f"ACCU : {str(node.children[1]).upper()}; into the RULEBLOCK that concludes {var}",
                    node.children[0],
                )

    def _mf(self, var: str, term: str, node: Tree):
        where = f"variable {var!r}, term {term!r}"  # the location is the error's file:line:col
        nums: list[float] = []
        for child in node.children:
            if isinstance(child, Tree):  # a point
                nums.extend(float(t) for t in child.children)
            elif child.type == "NUMBER":
                nums.append(float(child))
        if node.data == "mf_function":
            return self._function(var, term, node)
        if node.data == "mf_points":
            shape = "points"
        elif node.data == "mf_singleton":
            shape = "singleton"
            self.spikes.setdefault(var, node)
        else:
            word = str(node.children[0]).lower()
            if word in _UNSUPPORTED:
                raise self.error(
                    f"membership function {node.children[0]!s} is not supported; "
                    "use trian, trape, gauss, gbell, sigm, a point list or a singleton",
                    node.children[0],
                )
            if word not in _SHAPES:
                raise self.error(
                    f"unknown membership function {node.children[0]!s}", node.children[0]
                )
            shape = _SHAPES[word]
        if shape in ("triangle", "trapezoid", "points"):
            xs = nums if shape != "points" else nums[0::2]
            if xs and min(xs) == max(xs) and (shape != "points" or max(nums[1::2]) == 1.0):
                # zero width: jFuzzyLogic reads a spike at that x (1 there, 0 elsewhere)
                self.spikes.setdefault(var, node)
                shape, nums = "singleton", [xs[0]]
        try:
            return make_membership(shape, nums, where=where)
        except RuleError as exc:
            raise RuleError(
                exc.message, file=self.file, line=node.meta.line, column=node.meta.column
            ) from None

    def _function(self, var: str, term: str, node: Tree):
        """A FUNCTION term: an output's singleton at a point computed from the inputs."""
        body = str(node.children[0])[len("function") :]
        where = f"FUNCTION term {term} of {var}"
        if var in self.inputs:
            raise self.error(
                f"{where}: a FUNCTION term in FUZZIFY is 1 only where the input equals the "
                "function's value (jFuzzyLogic reads it, no measured input would fire it); give "
                f"{term} a shape",
                node,
            )
        try:
            expr = parse_function(body, where)
        except RuleError as exc:
            raise self.error(exc.message, node) from None
        for name in expr.variables:
            if name not in self.inputs:
                raise self.error(
                    f"{where} reads {name}, which is not declared in VAR_INPUT (jFuzzyLogic's "
                    "functions read inputs only); declare it there",
                    node,
                )
        self.functions.setdefault(var, node)
        return function_membership(expr)

    def _define(self, engine: FuzzyEngine, var: str) -> None:
        info = self.fuzz.get(var)
        is_out = var in self.outputs
        where = self.blocks.get(var) or self.declared_at[var]
        if is_out and info is None:
            raise self.error(f"output {var} has no DEFUZZIFY block; add one with its terms", where)
        info = info or {"terms": {}, "range": None, "method": None, "default": None, "nc": False}
        rng = info["range"] or (self.outputs if is_out else self.inputs).get(var)
        if var in self.functions:
            if not all(mf.singleton for mf in info["terms"].values()):
                raise self.error(
                    f"output {var} mixes FUNCTION terms with shaped ones; a FUNCTION term is a "
                    "singleton, so every term of the output must be one (jFuzzyLogic refuses the "
                    "mix when firing)",
                    self.functions[var],
                )
            if rng is None:
                raise self.error(
                    f"output {var} has FUNCTION terms: its range cannot be told from them; "
                    "give it RANGE := (min .. max);",
                    self.functions[var],
                )
        if is_out and var in self.spikes and not all(mf.singleton for mf in info["terms"].values()):
            # As jFuzzyLogic: a spike in a sampled continuous output has no width, so no method
            # sees it. Read, and said (the first one, with the count).
            spike = self.spikes[var]
            count = sum(mf.singleton for mf in info["terms"].values())
            log.warning(
                "%s: %d singleton or zero-width term(s) of output %s beside shaped ones (the first "
                "here): no "
                "width, so no defuzzification method sees them, as in jFuzzyLogic; give them a "
                "width, or make every term of %s a singleton",
                self.error("", spike).location(),
                count,
                var,
                var,
            )
        if rng is None:
            extents = [mf.extent() for mf in info["terms"].values()]
            if not extents:
                if not is_out:  # jFuzzyLogic loads it; no rule can use a variable without terms
                    self.untermed.add(var)
                    return
                raise self.error(f"variable {var} has no terms and no RANGE; give it one", where)
            lo, hi = min(a for a, _ in extents), max(b for _, b in extents)
            if lo == hi:  # spikes only, at one x: a universe around it
                lo, hi = lo - 1.0, hi + 1.0
        else:
            lo, hi = rng[0], rng[1]
        try:
            engine.define_variable(
                var,
                lo,
                hi,
                info["terms"],
                default=info["default"],
                keep_last=info["nc"],
                method=info["method"],
            )
        except RuleError as exc:
            raise self.error(exc.message, rng[2] if rng else where) from None

    def _ruleblock(self, engine: FuzzyEngine, node: Tree) -> None:
        name = str(node.children[1])
        ops: dict[str, str] = {}
        samples = None
        rules = []
        for index, item in enumerate(node.children[2:], start=2):
            if isinstance(item, Token) and item.type == "PRAGMA":
                m = re.search(r"samples\s*=\s*(\d+)", str(item))
                if not m:
                    raise self.error(
                        "unknown acordcs pragma; the only one is (*@acordcs samples=N *)", item
                    )
                samples = int(m.group(1))
            elif isinstance(item, Tree) and item.data == "operator":
                key, value = str(item.children[0]).upper(), item.children[1]
                allowed = {"AND": tuple(AND_OPS), "OR": OR_OPS, "ACT": ACT_OPS, "ACCU": ACCU_OPS}[
                    key
                ]
                if str(value).upper() not in allowed:
                    raise self.error(
                        f"unknown {key} operator {value!s} in RULEBLOCK {name}; use one of {', '.join(allowed)}",
                        value,
                    )
                ops[key] = str(value).upper()
            elif isinstance(item, Tree) and item.data == "rule":
                rules.append(index)
        and_ = ops.get("AND", FCL_DEFAULTS.and_)
        sem = FCL_DEFAULTS.with_(
            and_=and_,
            or_=ops.get("OR", AND_OPS[and_]),
            act=ops.get("ACT", FCL_DEFAULTS.act),
            accu=ops.get("ACCU", FCL_DEFAULTS.accu),
            samples=samples,
        )
        engine.define_ruleset(name, sem)
        labels: set[str] = set()
        for index in rules:
            item = node.children[index]
            # The engine keeps the rule from here: its tree goes, so that a file's peak memory is
            # not its whole tree plus its whole engine (a 1 MB file: 104 MB of tree).
            node.children[index] = None
            rule = self._rule(item)
            label = rule.label or ""
            if label in labels:  # jFuzzyLogic keeps both rules of one number: so do we, as N.2
                label = next(
                    f"{label}.{k}"
                    for k in range(2, len(labels) + 3)
                    if f"{label}.{k}" not in labels
                )
                rule = Rule("fuzzy", label, rule.condition, rule.actions, rule.weight, rule.text)
            labels.add(label)
            try:
                engine.add_rule(rule, name, file=self.file, line=item.meta.line)
            except RuleError as exc:
                if exc.column:
                    raise
                raise self.error(exc.message, item) from None

    def _rule(self, node: Tree) -> Rule:
        label = str(node.children[1])
        cond = _condition(node.children[3])
        if deepest(cond):
            raise self.error(f"rule {label}: {depth_message()}", node.children[3])
        for used in names_in(cond):
            if used.text in self.untermed:
                raise self.error(
                    f"rule {label}: variable {used.text} has no terms; define them in FUZZIFY {used.text}",
                    node.children[3],
                )
        actions = []
        weight = 1.0
        for child in node.children[5:]:
            if isinstance(child, Tree) and child.data == "conclusion":
                var, _, term = child.children
                actions.append(Consequent(_name(var), _name(term)))
            elif isinstance(child, Tree) and child.data == "weight":
                weight = float(child.children[1])
                if not 0.0 <= weight <= 1.0:
                    raise self.error(
                        f"rule {label}: weight {weight!r} is outside 0..1", child.children[1]
                    )
        text = format_rule(cond, actions, weight)
        return Rule("fuzzy", label, cond, tuple(actions), weight, text)


def _name(tok: Token) -> Name:
    return Name(str(tok), tok.column or 0)


def _condition(node: Tree) -> object:
    """The condition tree of a lark ``cond``, built without recursion (a chain of 10,000 ANDs
    nests 10,000 deep); the caller checks the depth against the rule language's limit."""
    out: list[object] = []
    stack: list[tuple[Tree, bool]] = [(node, False)]
    while stack:
        n, built = stack.pop()
        if n.data == "c_is":
            var, _is, *mods, term = n.children
            out.append(Is(_name(var), tuple(str(m).lower() for m in mods), _name(term)))
        elif not built:  # children first, then this node from their results
            stack.append((n, True))
            if n.data == "c_not":
                stack.append((n.children[1], False))
            else:
                stack.extend(((n.children[2], False), (n.children[0], False)))
        elif n.data == "c_not":
            out.append(Not(out.pop()))
        else:
            right, left = out.pop(), out.pop()
            out.append(BoolOp("and" if n.data == "c_and" else "or", left, right))
    return out[0]
