"""Parsing a model's rules from its raw bytes while libxml2 parses the file (``acordcs-gen``).

``acordcs-gen validate`` parses the model on a second thread (:func:`acordcs.generator.xmlsafe.
prefetch`); the main thread finishes its imports first and would then wait. It spends the wait
here: it finds the values of rule tags in the file's bytes and parses them into
:func:`acordcs.metamodel.rules.parse_rule`'s cache, where the rules check finds them. The texts
found need not be exact: the cache is keyed by the text, so a text read wrongly here costs only
a wasted parse, and the check parses what the reader read.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from acordcs.metamodel.rules import parse_rule, split_rules

# BOUML: <taggedValue tag="ACORDCS:CtxPolicy:Rule.." value=".."/> in xmi:Extension blocks; BOUML
# root applications and Eclipse: <ACORDCS:CtxPolicy .. Rule..=".."/>. The literal start lets the
# regex engine skip ahead (4.6 MB in 3 ms; a lookbehind in front would cost it: 78 ms); what else
# it matches is only a wasted parse. The lookbehind after 'Rule' keeps matches to the start of a
# word: in 'RuleRuleRule...' every 'Rule' would otherwise start a scan to the end of the run
# (quadratic: a hostile 80 KB comment took 19 s).
_RULE_VALUE = re.compile(rb'Rule(?<!\wRule)\w*(?:\s*=\s*|"\s+value\s*=\s*)"([^"<]*)"')
_REFERENCE = re.compile(r"&(#x[0-9a-fA-F]+|#[0-9]+|lt|gt|amp|quot|apos);")
_NAMED = {"lt": "<", "gt": ">", "amp": "&", "quot": '"', "apos": "'"}
_LITERAL_BLANKS = str.maketrans("\t\n\r", "   ")  # XML normalises them in attribute values


def _character(match: re.Match) -> str:
    ref = match.group(1)
    if ref[0] != "#":
        return _NAMED[ref]
    try:
        return chr(int(ref[2:], 16) if ref[1] == "x" else int(ref[1:]))
    except (ValueError, OverflowError):
        return match.group(0)


def warm(data: bytes, stop: Callable[[], bool] = lambda: False) -> int:
    """Parse the rules of the rule tags found in ``data`` (fuzzy, else crisp: the engine of their
    policy set is not known here) until ``stop()``; return how many parsed."""
    parsed = 0
    done: set[bytes] = set()
    for match in _RULE_VALUE.finditer(data):
        if stop():
            break
        raw = match.group(1)
        if raw in done:
            continue
        done.add(raw)
        value = _REFERENCE.sub(
            _character, raw.decode("utf-8", "replace").translate(_LITERAL_BLANKS)
        )
        for line in split_rules(value):
            for kind in ("fuzzy", "crisp"):
                try:
                    parse_rule(line.text, kind)
                except Exception:  # errors, texts that are no rules: the check will tell
                    continue
                parsed += 1
                break
    return parsed
