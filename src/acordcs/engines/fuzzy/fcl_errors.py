"""What the FCL reader says when lark cannot parse a file: the statement's FUNCTION definition,
a missing END_ (naming the block left open and where it opened), or the token found and the ones
expected, at file:line:column."""

from __future__ import annotations

import re

from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from acordcs.engines.rule_engine import RuleError

_FUNCTION = re.compile(r"(?i)\bfunction\b")


def _position(text: str, pos: int) -> tuple[int, int]:
    """1-based line and column of offset ``pos`` in ``text``."""
    return text.count("\n", 0, pos) + 1, pos - text.rfind("\n", 0, pos)


def syntax_error(err: UnexpectedInput, text: str, filename: str | None) -> RuleError:
    line, column = getattr(err, "line", None), getattr(err, "column", None)
    pos = getattr(err, "pos_in_stream", None)
    if pos is None and isinstance(err, UnexpectedToken):
        pos = err.token.start_pos
    pos = len(text) if pos is None or pos < 0 else pos
    # The statement the parse stopped in (from the previous ';'): a FUNCTION there is the cause
    start = text.rfind(";", 0, pos) + 1
    used = _FUNCTION.search(text, start, max(pos + 8, start))
    if used:
        line, column = _position(text, used.start())
        return RuleError(
            "FUNCTION definitions (IEC 61131-3 program code) are not read; an FCL file holds "
            "FUNCTION_BLOCKs (a FUNCTION term, TERM t := FUNCTION <expression>;, is read)",
            file=filename,
            line=line,
            column=column,
        )
    if isinstance(err, UnexpectedToken):
        found = "end of file" if err.token.type == "$END" else repr(str(err.token))
        expected = sorted(err.expected)
        ends = [e for e in expected if e.startswith("END_")]
        if ends:
            pos = err.token.start_pos if err.token.start_pos is not None else len(text)
            # LALR merges states, so several END_s may be expected: the latest opened block wins
            openers = {
                e: [m.start() for m in re.finditer(rf"(?i)\b{e[4:]}\b", text[:pos])] for e in ends
            }
            end = max(ends, key=lambda e: openers[e][-1] if openers[e] else -1)
            opener, opened = end[4:], openers[end]
            where = f" (opened at line {text.count(chr(10), 0, opened[-1]) + 1})" if opened else ""
            msg = f"missing {end}: the {opener} block{where} is not closed before {found}"
            if err.token.type == "$END":  # after the last character of the file
                line, column = _position(text, len(text.rstrip()))
            return RuleError(msg + f"; add {end}", file=filename, line=line, column=column)
        words = ", ".join(e.lower() if e.isupper() and len(e) > 2 else e for e in expected[:8])
        return RuleError(
            f"unexpected {found}; expected one of: {words}", file=filename, line=line, column=column
        )
    if isinstance(err, UnexpectedCharacters):
        ch = text[err.pos_in_stream] if err.pos_in_stream < len(text) else "end of file"
        return RuleError(f"unexpected character {ch!r}", file=filename, line=line, column=column)
    return RuleError("FCL syntax error", file=filename, line=line, column=column)
