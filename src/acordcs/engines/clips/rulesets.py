"""Rule sets as CLIPS modules: defining crisp and native rules, replacing them by label.

A rule set is a module importing MAIN. Crisp rules carry saliences 9999, 9998, ... in the order
they were first defined, so the first rule whose condition holds fires first; a rule replaced by
label keeps its place. Native rules keep their own salience (CLIPS default 0).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from clips import Symbol

from acordcs.engines.clips.bridge import Bridge, ClipsFailure
from acordcs.engines.clips.clips_compiler import OperationResolver, VariableResolver, compile_rule
from acordcs.engines.clips.records import Sites
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import RuleSyntaxError, parse_rule
from acordcs.rules.binding import default_label

_SET_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_NATIVE_HEAD = re.compile(r"\(\s*defrule\s+([^\s()\";&|~<>]+)")
_LABEL = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*:")
_MAX_CRISP_RULES = 19_999  # saliences 9999 down to -9999, CLIPS's range


@dataclass(slots=True)
class Entry:
    label: str
    kind: str  # "crisp" or "native"
    clips_name: str
    source: str
    constructs: tuple[str, ...]
    position: int
    rule_id: int = 0  # crisp rules: the number in their "fired" global ?*acord-f<id>*


@dataclass(slots=True)
class RuleSet:
    name: str
    symbol: Symbol
    rules: dict[str, Entry] = field(default_factory=dict)
    next_position: int = 0
    natives: bool = False  # whether (acord-fire) must be asserted
    # push functions by pattern of changed variables (see ClipsEngine._push_call)
    pushers: dict[tuple[int, ...], bytes] = field(default_factory=dict)


class RuleSets:
    """The rule sets of one engine, and the labels of rule numbers (for fault reports)."""

    def __init__(self, bridge: Bridge, variables: VariableResolver, operations: OperationResolver):
        self.bridge = bridge
        self.variables = variables
        self.operations = operations
        self.sites = Sites()  # what the negative records of crisp rules stand for
        self.sets: dict[str, RuleSet] = {}
        self.labels: dict[int, str] = {}
        self.read: set[int] = set()  # variables with an acord-var fact: some crisp rule reads them

    def define(self, rule: str, ruleset: str, priority: int | None = None) -> str:
        target = self.ensure(ruleset)
        text = rule.strip()
        if text.startswith("("):
            return self.define_native(target, text)
        return self.define_crisp(target, text, priority)

    def ensure(self, name: str) -> RuleSet:
        found = self.sets.get(name)
        if found is not None:
            return found
        if not isinstance(name, str) or not _SET_NAME.match(name) or name == "MAIN":
            raise RuleError(
                f"{name!r} cannot name a rule set: use an identifier (letters, digits, _), not MAIN",
                ruleset=str(name),
            )
        try:
            self.bridge.build(f"(defmodule {name} (import MAIN ?ALL))")
        except ClipsFailure as err:
            raise RuleError(
                f"CLIPS cannot make module {name!r}: {err}; use another rule set name"
            ) from None
        found = self.sets[name] = RuleSet(name, Symbol(name))
        return found

    def define_crisp(self, target: RuleSet, text: str, priority: int | None = None) -> str:
        """Define (or replace by label) a crisp rule; ``priority``: its 1-based rank (salience
        9999 for 1, 9998 for 2...), else after the rules defined so far (a replaced rule keeps
        its place)."""
        guess = _LABEL.match(text)
        try:
            parsed = parse_rule(text, "crisp")
        except RuleSyntaxError as err:
            label = guess.group(1) if guess else None
            raise RuleError(
                err.message, ruleset=target.name, rule=label, column=err.column
            ) from None
        label = parsed.label or self._auto_label(target)
        old = target.rules.get(label)
        keep = old is not None and old.kind == "crisp"  # a crisp rule replaced keeps its place
        if priority is not None:
            position, keep = priority - 1, True
            target.next_position = max(target.next_position, priority)
        else:
            position = old.position if keep else target.next_position
        if position > _MAX_CRISP_RULES:
            raise RuleError(
                f"a rule set holds at most {_MAX_CRISP_RULES + 1} rules",
                ruleset=target.name,
                rule=label,
            )
        rule_id = len(self.labels) + 1
        compiled = compile_rule(
            parsed,
            ruleset=target.name,
            module=target.name,
            label=label,
            rule_id=rule_id,
            salience=9999 - position,
            variables=self.variables,
            operations=self.operations,
            sites=self.sites,
        )
        self.labels[rule_id] = label
        for index in compiled.reads:
            if index not in self.read:
                # A variable's fact exists once a rule reads it (see compiler.touch); a fact
                # asserted now is matched by the rule when it is built, like any older fact.
                self.bridge.run(f"(bind ?*acord-vf{index}* (assert (acord-var (i {index}))))")
                self.read.add(index)
        entry = Entry(
            label, "crisp", f"{target.name}::{label}", text, compiled.constructs, position, rule_id
        )
        self._install(target, entry, old)
        if not keep:
            target.next_position += 1
        return label

    def define_native(self, target: RuleSet, text: str) -> str:
        head = _NATIVE_HEAD.match(text)
        if head is None:
            raise RuleError(
                "native CLIPS text must be one (defrule name ...) construct",
                ruleset=target.name,
                column=1,
            )
        module, _, label = head.group(1).rpartition("::")
        if module and module != target.name:
            raise RuleError(
                f"the rule names module {module!r} but belongs to rule set {target.name!r}; drop '{module}::'",
                ruleset=target.name,
                rule=label,
                column=head.start(1) + 1,
            )
        old = target.rules.get(label)
        entry = Entry(
            label, "native", f"{target.name}::{label}", text, (text,), old.position if old else -1
        )
        self._install(target, entry, old)
        if not target.natives:
            target.natives = True
            target.pushers.clear()  # they were built not to assert (acord-fire)
        return label

    def _install(self, target: RuleSet, entry: Entry, old: Entry | None) -> None:
        native = entry.kind == "native"
        try:
            for construct in entry.constructs:
                self.bridge.build(construct, module=target.name if native else None)
        except ClipsFailure as err:
            if old is not None and old.clips_name == entry.clips_name:
                # CLIPS drops a rule whose redefinition fails: put the old one back.
                for construct in old.constructs:
                    self.bridge.build(
                        construct, module=target.name if old.kind == "native" else None
                    )
            raise RuleError(
                f"CLIPS rejected the rule: {err}", ruleset=target.name, rule=entry.label
            ) from None
        if old is not None and old.clips_name != entry.clips_name:
            self.bridge.undefine_rule(old.clips_name)
        target.rules[entry.label] = entry

    def _auto_label(self, target: RuleSet) -> str:
        return default_label(len(target.rules) + 1, target.rules)
