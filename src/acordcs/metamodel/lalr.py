"""A lean LALR(1) driver for the tables lark computes from a grammar: lark analyses, we parse.

lark is the grammar compiler: it reads the ``.lark`` file and computes the LALR(1) parse table and
the contextual lexer (one scanner per parser state). Its own parse loop takes about 120 µs for a
fifteen-token rule (this one about 40) and importing it about 45 ms: a large share of
``acordcs-gen validate`` on a large model (``benchmarks/bench_validate.py`` measures both). So the analysis is done once and kept as plain data (JSON) in the private cache
directory (see :mod:`acordcs.cachedir`), and this module runs the same automaton with the same
tree-building rules (child filtering, ``_rule`` inlining, ``?rule`` single-child expansion,
``[]`` placeholders) without importing lark. ``tests/test_rules_lalr.py`` holds it to lark's own
parser, trees and errors alike, on generated input.

The input is one line (columns are offsets + 1): the rule language has no multi-line constructs.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections.abc import Callable, Iterable, Mapping

from acordcs.cachedir import private_dir

# Bump when the layout of the stored tables, or what the driver expects of them, changes.
TABLE_FORMAT = 1


class Unexpected(Exception):
    """Where parsing stopped. ``found`` is the text of the token (None: end of input), ``expected``
    the terminal names allowed there (None: no terminal matches the character at ``column``)."""

    def __init__(self, found: str | None, column: int, expected: frozenset[str] | None) -> None:
        super().__init__(found, column, expected)
        self.found = found
        self.column = column
        self.expected = expected


class Tok:
    """A token handed to the tree builders: its terminal name, text and 1-based column."""

    __slots__ = ("column", "text", "type")

    def __init__(self, type: str, text: str, column: int) -> None:
        self.type = type
        self.text = text
        self.column = column

    def __repr__(self) -> str:
        return f"Tok({self.type}, {self.text!r}, {self.column})"


class Node:
    """The result of a rule without a builder (``start`` rules, lark's ``_``-rules)."""

    __slots__ = ("children", "data")

    def __init__(self, data: str, children: list) -> None:
        self.data = data
        self.children = children


class _Scanner:
    __slots__ = ("allowed", "blanks", "match", "unless")

    def __init__(self, spec: dict) -> None:
        # Ignored text (blanks) is skipped by the same regular expression that reads the token
        # after it: one match per token, not two. This equals lark's loop because no terminal of
        # the grammar can begin with ignored text (the oracle test would show it otherwise).
        skip = "|".join(f"(?:{p})" for p in spec["ignore"])
        # Atomic: blanks once skipped are never given back. A backtracking (?:(?: |\t)+)* would
        # try every way of splitting a run of n blanks before a bad character: 2**n steps.
        blanks = f"(?>(?:{skip})*)" if skip else ""
        self.match = re.compile(f"{blanks}(?:{spec['pattern']})", spec["flags"]).match
        self.blanks = re.compile(blanks, spec["flags"]).match  # always matches, maybe nothing
        self.unless = spec["unless"]  # terminal -> {exact text: string terminal it really is}
        self.allowed = frozenset(spec["allowed"])


class _Rule:
    __slots__ = ("append_none", "callback", "expand1", "keep", "origin", "size")

    def __init__(self, spec: dict) -> None:
        self.origin = spec["origin"]
        self.size = spec["size"]
        self.callback = spec["callback"]
        keep = spec["keep"]  # [[index, splice, nones before]] or None: every child as it is
        self.keep = None if keep is None else [tuple(k) for k in keep]
        self.append_none = spec["append_none"]
        self.expand1 = spec["expand1"]


class Tables:
    """The parse table and scanners of one grammar, and the parse loop that runs them."""

    def __init__(self, data: dict) -> None:
        if data.get("format") != TABLE_FORMAT:
            raise ValueError("stored parse tables have another format")
        scanners = [_Scanner(s) for s in data["scanners"]]
        self._rules = [_Rule(r) for r in data["rules"]]
        # Actions: a state number to shift to (>= 0), or -1 - the index of the rule to reduce by.
        self._actions: list[dict[str, int]] = data["actions"]
        self._scanner_of = [scanners[i] for i in data["scanner_of"]]
        self._root = scanners[data["root_scanner"]]
        self._start: dict[str, int] = data["start"]
        self._end: dict[str, int] = data["end"]

    # ------------------------------------------------------------------------------ building
    @classmethod
    def for_grammar(cls, grammar: str, starts: Iterable[str], name: str) -> Tables:
        """Tables for ``grammar``: from the private cache, else analysed by lark (and stored)."""
        starts = list(starts)
        key = hashlib.sha256(f"{TABLE_FORMAT}\0{starts}\0{grammar}".encode()).hexdigest()[:32]
        directory = private_dir()
        path = os.path.join(directory, f"{name}-{key}.lalr.json") if directory else None
        if path is not None:
            try:
                with open(path, encoding="utf-8") as handle:
                    return cls(json.load(handle))
            except (OSError, ValueError, KeyError, TypeError, re.error):
                pass  # absent, or not what this version writes: analyse again
        data = analyse(grammar, starts)
        if path is not None:
            _store(path, data)
        return cls(data)

    # ------------------------------------------------------------------------------- parsing
    def parse(self, text: str, start: str, builders: Mapping[str, Callable]) -> object:
        """Parse one line of ``text`` from rule ``start``; ``builders`` map rule names (or aliases)
        to functions of the rule's kept children. Raises :class:`Unexpected`."""
        if "\n" in text:
            raise ValueError("the LALR driver reads one line at a time")
        actions = self._actions
        scanner_of = self._scanner_of
        rules = self._rules
        end_state = self._end[start]
        states = [self._start[start]]
        values: list = []
        pos = 0
        length = len(text)
        while True:
            # The scanner of the state reached so far: the contextual lexing lark does.
            token = None
            if pos < length:
                scanner = scanner_of[states[-1]]
                found = scanner.match(text, pos)
                if found is not None:
                    kind = found.lastgroup
                    value = found.group(kind)
                    if kind in scanner.unless:
                        kind = scanner.unless[kind].get(value, kind)
                    token = Tok(kind, value, found.start(kind) + 1)
                    pos = found.end()
                else:
                    pos = scanner.blanks(text, pos).end()
                    if pos < length:
                        raise self._bad_character(text, pos, scanner)
            kind = token.type if token is not None else "$END"
            while True:
                state = states[-1]
                action = actions[state].get(kind)
                if action is None:
                    expected = frozenset(s for s in actions[state] if s.isupper())
                    if token is None:
                        raise Unexpected(None, length + 1, expected)
                    raise Unexpected(token.text, token.column, expected)
                if action >= 0:  # shift the token, then read the next one
                    states.append(action)
                    values.append(token)
                    break
                rule = rules[-1 - action]
                size = rule.size
                if size:
                    children = values[-size:]
                    del states[-size:]
                    del values[-size:]
                else:
                    children = []
                states.append(actions[states[-1]][rule.origin])
                values.append(_build(rule, children, builders))
                if token is None and states[-1] == end_state:
                    return values[-1]

    def _bad_character(self, text: str, pos: int, scanner: _Scanner) -> Unexpected:
        """``pos``: the first character after blanks that the state's scanner cannot read."""
        # As lark: a token of the grammar that is not allowed here is reported as that token.
        found = self._root.match(text, pos)
        if found is None:
            return Unexpected(None, pos + 1, None)
        kind = found.lastgroup
        return Unexpected(found.group(kind), found.start(kind) + 1, scanner.allowed)


def _build(rule: _Rule, children: list, builders: Mapping[str, Callable]) -> object:
    if rule.keep is not None:
        kept: list = []
        for index, splice, nones in rule.keep:
            if nones:
                kept += [None] * nones
            if splice:
                kept += children[index].children
            else:
                kept.append(children[index])
        if rule.append_none:
            kept += [None] * rule.append_none
        children = kept
    if rule.expand1 and len(children) == 1:
        return children[0]
    build = builders.get(rule.callback)
    return build(*children) if build is not None else Node(rule.callback, children)


def _store(path: str, data: dict) -> None:
    import tempfile  # only on a cache miss: it costs start-up time

    try:
        fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), suffix=".tmp")
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            json.dump(data, handle, separators=(",", ":"))
        os.replace(tmp, path)
    except OSError:
        pass  # a read-only cache only costs start-up time


# ------------------------------------------------------------------------------ the analysis
def analyse(grammar: str, starts: list[str]) -> dict:
    """Let lark analyse ``grammar`` (LALR(1), contextual lexer, ``maybe_placeholders``) and return
    its automaton as plain data for :class:`Tables`."""
    from lark.parsers.lalr_analysis import Shift

    frontend = lark_parser(grammar, starts).parser
    table = frontend.parser.parser.parse_table
    contextual = frontend.lexer
    scanners: list[dict] = []
    scanner_index: dict[int, int] = {}

    def scanner_id(lexer) -> int:
        if id(lexer) not in scanner_index:
            scanner_index[id(lexer)] = len(scanners)
            scanners.append(_scanner_spec(lexer))
        return scanner_index[id(lexer)]

    rules: list = []
    rule_index: dict = {}
    actions: list[dict[str, int]] = [{} for _ in range(len(table.states))]
    for state, row in table.states.items():
        for symbol, (action, arg) in row.items():
            if action is Shift:
                actions[state][symbol] = arg
            else:
                if arg not in rule_index:
                    rule_index[arg] = len(rules)
                    rules.append(arg)
                actions[state][symbol] = -1 - rule_index[arg]
    return {
        "format": TABLE_FORMAT,
        "actions": actions,
        "rules": [_rule_spec(rule) for rule in rules],
        "scanners": scanners,
        "scanner_of": [scanner_id(contextual.lexers[s]) for s in range(len(table.states))],
        "root_scanner": scanner_id(contextual.root_lexer),
        "start": dict(table.start_states),
        "end": dict(table.end_states),
    }


def lark_parser(grammar: str, starts: list[str], builders: Mapping[str, Callable] | None = None):
    """lark's own parser for ``grammar``, as :func:`analyse` configures it; with ``builders``, it
    builds trees with them as :meth:`Tables.parse` does (tokens as :class:`Tok`): the oracle the
    tests and ``benchmarks/bench_validate.py`` compare this module with."""
    from lark import Lark, Token, Transformer

    class SameBuilders(Transformer):
        def __default__(self, data, children, meta):
            kids = [Tok(c.type, str(c), c.column) if isinstance(c, Token) else c for c in children]
            build = builders.get(data)
            return build(*kids) if build is not None else Node(data, kids)

    return Lark(
        grammar,
        start=starts,
        parser="lalr",
        lexer="contextual",
        maybe_placeholders=True,
        transformer=SameBuilders() if builders is not None else None,
    )


def _scanner_spec(lexer) -> dict:
    scanner = lexer.scanner  # built on first use; builds lexer.callback too
    unless = {}
    for kind, callback in lexer.callback.items():
        strings = getattr(callback, "scanner", None)
        if strings is None or any(t.pattern.flags for t in strings.terminals):
            raise ValueError(f"lexer callback on {kind}: not supported")
        unless[kind] = {t.pattern.value: t.name for t in strings.terminals}
    ignored = lexer.ignore_types
    # The scanner's own terminals, in its order of preference: Python's re takes the first
    # alternative that matches, as lark's scanner does.
    tokens = [t for t in scanner.terminals if t.name not in ignored]
    pattern = "|".join(f"(?P<{t.name}>{t.pattern.to_regexp()})" for t in tokens) or "(?!)"
    return {
        "pattern": pattern,
        "flags": scanner._mres[0].flags,
        "ignore": [t.pattern.to_regexp() for t in scanner.terminals if t.name in ignored],
        "unless": unless,
        "allowed": sorted((scanner.allowed_types - ignored) or {"<END-OF-FILE>"}),
    }


def _rule_spec(rule) -> dict:
    # lark's parse_tree_builder: which children a rule keeps, which it inlines, where a missing
    # [optional] leaves None, and whether a ?rule with one child is replaced by that child.
    expansion = rule.expansion
    options = rule.options
    empty = list(options.empty_indices or ())
    if empty:
        flags = "".join(str(int(b)) for b in empty)
        nones_at = [len(ones) for ones in flags.split("0")]
    else:
        nones_at = [0] * (len(expansion) + 1)
    keep = []
    pending = 0
    for index, symbol in enumerate(expansion):
        pending += nones_at[index]
        if options.keep_all_tokens or not (symbol.is_term and symbol.filter_out):
            splice = not symbol.is_term and symbol.name.startswith("_")
            keep.append([index, splice, pending])
            pending = 0
    pending += nones_at[len(expansion)]
    filtering = empty or len(keep) < len(expansion) or any(k[1] for k in keep)
    return {
        "origin": rule.origin.name,
        "size": len(expansion),
        "callback": rule.alias or options.template_source or rule.origin.name,
        "keep": keep if filtering else None,
        "append_none": pending if filtering else 0,
        "expand1": bool(options.expand1 and not rule.alias),
    }
