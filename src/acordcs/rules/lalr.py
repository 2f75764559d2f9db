"""A lean LALR(1) driver for the tables lark computes from a grammar: lark analyses, we parse.

lark is the grammar compiler: it reads the ``.lark`` file and computes the LALR(1) parse table and
the contextual lexer (one scanner per parser state). Its own parse loop takes about 120 µs for a
fifteen-token rule (this one about 30) and importing it about 45 ms: a large share of
``acordcs-gen validate`` on a large model (``benchmarks/bench_validate.py`` measures both). So the analysis is done once and kept as plain data (JSON) in the private cache
directory (see :mod:`acordcs.cachedir`), and this module runs the same automaton with the same
tree-building rules (child filtering, ``_rule`` inlining, ``?rule`` single-child expansion,
``[]`` placeholders) without importing lark. ``tests/rules/test_lalr_matches_lark.py`` holds it to lark's own
parser, trees and errors alike, on generated input.

The input is one line (columns are offsets + 1): the rule language has no multi-line constructs.
"""

from __future__ import annotations

import json
import os
import re
import zlib
from collections.abc import Callable, Iterable, Mapping
from operator import itemgetter

from acordcs.cachedir import private_dir

# Bump when the layout of the stored tables, or what the driver expects of them, changes.
TABLE_FORMAT = 2


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
    __slots__ = ("_blanks", "_flags", "_pattern", "allowed", "match", "unless")

    def __init__(self, spec: dict) -> None:
        # Ignored text (blanks) is skipped by the same regular expression that reads the token
        # after it: one match per token, not two. This equals lark's loop because no terminal of
        # the grammar can begin with ignored text (the oracle test would show it otherwise).
        skip = "|".join(f"(?:{p})" for p in spec["ignore"])
        # Atomic: blanks once skipped are never given back. A backtracking (?:(?: |\t)+)* would
        # try every way of splitting a run of n blanks before a bad character: 2**n steps.
        self._blanks = f"(?>(?:{skip})*)" if skip else ""
        self._pattern = f"{self._blanks}(?:{spec['pattern']})"
        self._flags = spec["flags"]
        # Compiled on first use: compiling every state's scanner costs about 9 ms (Python's
        # regex compiler is slow), and a run visits about half of them.
        self.match: Callable = self._compile
        self.unless = spec["unless"] or None  # terminal -> {exact text: string terminal it is}
        self.allowed = frozenset(spec["allowed"])

    def _compile(self, text: str, pos: int) -> re.Match | None:
        self.match = re.compile(self._pattern, self._flags).match
        return self.match(text, pos)

    def blanks(self, text: str, pos: int) -> re.Match:
        """Skip blanks from ``pos`` (always matches, maybe nothing); only on errors and at the end."""
        return re.compile(self._blanks, self._flags).match(text, pos)


# How a reduction builds its value (see _Rule.plan): the kept child at one index, unchanged; the
# builder (or a Node) on every child; on the children at some indices; anything else (inlined
# _rules, [] placeholders): the general _build.
_PASS, _ALL, _PICK, _GENERAL = range(4)


class _Rule:
    __slots__ = ("append_none", "callback", "expand1", "keep", "origin", "plan", "size")

    def __init__(self, spec: dict) -> None:
        self.origin = spec["origin"]
        self.size = spec["size"]
        self.callback = spec["callback"]
        keep = spec["keep"]  # [[index, splice, nones before]] or None: every child as it is
        self.keep = None if keep is None else [tuple(k) for k in keep]
        self.append_none = spec["append_none"]
        self.expand1 = spec["expand1"]
        self.plan = self._plan()

    def _plan(self) -> tuple:
        # What _build would do, decided once here instead of on every reduction.
        if self.keep is None:
            indices = list(range(self.size))
        elif self.append_none or any(splice or nones for _, splice, nones in self.keep):
            return (self.origin, self.size, _GENERAL, None, self.callback, self)
        else:
            indices = [index for index, _, _ in self.keep]
        if self.expand1 and len(indices) == 1:  # ?rule with one child: that child
            return (self.origin, self.size, _PASS, indices[0] - self.size, self.callback, self)
        if indices == list(range(self.size)):
            return (self.origin, self.size, _ALL, None, self.callback, self)
        pick = itemgetter(*indices) if len(indices) > 1 else lambda c, i=indices[0]: (c[i],)
        return (self.origin, self.size, _PICK, pick, self.callback, self)


class Tables:
    """The parse table and scanners of one grammar, and the parse loop that runs them."""

    def __init__(self, data: dict) -> None:
        if data.get("format") != TABLE_FORMAT:
            raise ValueError("stored parse tables have another format")
        scanners = [_Scanner(s) for s in data["scanners"]]
        self._rules = [_Rule(r) for r in data["rules"]]
        self._plans = [rule.plan for rule in self._rules]
        # Actions: a state number to shift to (>= 0), or -1 - the index of the rule to reduce by.
        self._actions: list[dict[str, int]] = data["actions"]
        self._scanner_of = [scanners[i] for i in data["scanner_of"]]
        self._root = scanners[data["root_scanner"]]
        self._start: dict[str, int] = data["start"]
        self._end: dict[str, int] = data["end"]
        if len(self._scanner_of) != len(self._actions):
            raise ValueError("stored parse tables are inconsistent")

    # ------------------------------------------------------------------------------ building
    @classmethod
    def for_grammar(cls, grammar: str, starts: Iterable[str], name: str) -> Tables:
        """Tables for ``grammar``: from the private cache, else analysed by lark (and stored)."""
        starts = list(starts)
        # The name only tells grammars apart; what a file holds is verified when it is read
        # (checksum, grammar, starts), so a cheap checksum serves (hashlib costs 3 ms to import).
        source = f"{TABLE_FORMAT}\0{starts}\0{grammar}".encode()
        key = f"{zlib.crc32(source):08x}{len(source):x}"
        directory = private_dir()
        path = os.path.join(directory, f"{name}-{key}.lalr.json") if directory else None
        if path is not None:
            try:
                with open(path, encoding="utf-8") as handle:
                    data = _load(handle.read())
                if data.get("grammar") == grammar and data.get("starts") == starts:
                    return cls(data)
            except (OSError, ValueError, LookupError, TypeError):
                pass  # absent, damaged, or not what this version writes: analyse again
        data = analyse(grammar, starts)
        if path is not None:
            _store(path, {**data, "grammar": grammar, "starts": starts})
        return cls(data)

    # ------------------------------------------------------------------------------- parsing
    def parse(self, text: str, start: str, builders: Mapping[str, Callable]) -> object:
        """Parse one line of ``text`` from rule ``start``; ``builders`` map rule names (or aliases)
        to functions of the rule's kept children. Raises :class:`Unexpected`."""
        if "\n" in text:
            raise ValueError("the LALR driver reads one line at a time")
        # The loop below is the hot path of validating a model's rules: names are local, the
        # current state is kept in a variable, and each reduction follows its rule's plan.
        actions = self._actions
        scanner_of = self._scanner_of
        plans = self._plans
        get = builders.get
        new = object.__new__
        end_state = self._end[start]
        state = self._start[start]
        states = [state]
        values: list = []
        push_state = states.append
        push_value = values.append
        pos = 0
        length = len(text)
        while True:
            # The scanner of the state reached so far: the contextual lexing lark does.
            if pos < length:
                scanner = scanner_of[state]
                found = scanner.match(text, pos)
                if found is None:
                    pos = scanner.blanks(text, pos).end()
                    if pos < length:
                        raise self._bad_character(text, pos, scanner)
                    token = None
                    kind = "$END"
                else:
                    kind = found.lastgroup
                    begin, pos = found.span(kind)
                    token = new(Tok)  # Tok(...) without the call of __init__
                    token.text = value = text[begin:pos]
                    token.column = begin + 1
                    if scanner.unless is not None and kind in scanner.unless:
                        kind = scanner.unless[kind].get(value, kind)
                    token.type = kind
            else:
                token = None
                kind = "$END"
            action = actions[state].get(kind)
            while True:
                if action is None:
                    expected = frozenset(s for s in actions[state] if s.isupper())
                    if token is None:
                        raise Unexpected(None, length + 1, expected)
                    raise Unexpected(token.text, token.column, expected)
                if action >= 0:  # shift the token, then read the next one
                    state = action
                    push_state(state)
                    push_value(token)
                    break
                origin, size, mode, arg, callback, rule = plans[~action]
                if mode == _PASS and size == 1:  # the value stays where it is
                    state = actions[states[-2]][origin]
                    states[-1] = state
                else:
                    if size:
                        children = values[-size:]
                        del values[-size:]
                        del states[-size:]
                    else:
                        children = []
                    if mode == _ALL:
                        build = get(callback)
                        value = build(*children) if build is not None else Node(callback, children)
                    elif mode == _PICK:
                        children = list(arg(children))
                        build = get(callback)
                        value = build(*children) if build is not None else Node(callback, children)
                    elif mode == _PASS:
                        value = children[arg]
                    else:
                        value = _build(rule, children, builders)
                    state = actions[states[-1]][origin]
                    push_state(state)
                    push_value(value)
                if token is None and state == end_state:
                    return values[-1]
                action = actions[state].get(kind)

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


# A stored file is JSON: {"format": F, "check": crc32 of the tables' text, "tables": {...}}. The
# checksum finds a damaged file before any of it is used (scanners are compiled only when needed,
# so a bad pattern would otherwise surface in the middle of a parse).
_HEAD = '{"format":%d,"check":'


def _load(stored: str) -> dict:
    head = _HEAD % TABLE_FORMAT
    if not stored.startswith(head) or not stored.endswith("}"):
        raise ValueError("not a table file of this version")
    check, sep, body = stored[len(head) : -1].partition(',"tables":')
    if not sep or not check.isdigit() or zlib.crc32(body.encode("utf-8")) != int(check):
        raise ValueError("damaged table file")
    data = json.loads(body)
    if not isinstance(data, dict):
        raise ValueError("damaged table file")
    return data


def _store(path: str, data: dict) -> None:
    import tempfile  # only on a cache miss: it costs start-up time

    body = json.dumps(data, separators=(",", ":"))
    try:
        fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), suffix=".tmp")
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            check = zlib.crc32(body.encode("utf-8"))
            handle.write(f'{_HEAD % TABLE_FORMAT}{check},"tables":{body}}}')
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
        "flags": re.compile(pattern, scanner.g_regex_flags).flags,  # as lark's scanner compiles it
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
