"""Helpers of the rule language tests."""

from __future__ import annotations

from acordcs.rules.lalr import Node, Tok


def plain(value):
    """A parse result of the LALR driver or of lark (same builders) as nested tuples and lists."""
    if isinstance(value, Node):
        return ("node", value.data, [plain(c) for c in value.children])
    if isinstance(value, Tok):
        return ("tok", value.type, value.text, value.column)
    if isinstance(value, tuple | list):
        return type(value)(plain(v) for v in value)
    return value
