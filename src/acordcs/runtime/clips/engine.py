"""ClipsEngine: the paper's four calls (defrule, set, fire, get) on CLIPS through clipspy.

Semantics of one ``fire(S)``:

1. the values set since the last fire go into CLIPS in one call, which then runs rule set S only
   (S is a CLIPS module, given the focus);
2. crisp rules are evaluated on the current values; the first rule in definition order whose
   condition holds fires, its actions run left to right; if it changed a value, the rules not yet
   fired are evaluated again; this goes on until no rule can fire. Each rule fires at most once per
   fire, so a rule whose action changes what its condition reads cannot loop;
3. native rules follow CLIPS (salience, refraction), bounded by ``max_firings`` per fire;
4. back in Python: assignments land in the value store (``get``), then the operations the rules
   called run, in firing order, with the argument values computed when the rule fired.

Nothing a rule does at fire time raises: evaluation errors (a string compared with a number, a
division by zero), unbound operations and operations that raise are logged with their rule set and
rule, counted in :attr:`ClipsEngine.error_count`, kept in :attr:`ClipsEngine.errors`, and the fire
carries on. Errors in what you define (syntax, unknown variable or operation) raise RuleError.
"""

from __future__ import annotations

import difflib
import re
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

from acordcs.metamodel.rules import Name
from acordcs.runtime.clips.bridge import Bridge, ClipsFailure
from acordcs.runtime.clips.compiler import Target
from acordcs.runtime.clips.operations import Faults, FireError, Operations
from acordcs.runtime.clips.prelude import FIRE, RUN, assign_dispatcher, pusher, put_dispatcher
from acordcs.runtime.clips.rulesets import RuleSet, RuleSets
from acordcs.runtime.clips.values import Value, from_clips, kind_of_type, normalise
from acordcs.runtime.engine import RuleError

__all__ = ["ClipsEngine", "FireError"]

_VARIABLE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*\Z")
_MAX_PUSHERS = 256  # distinct (rule set, variables set) patterns with their own push function


@dataclass(slots=True)
class _Variable:
    name: str
    index: int
    kind: str | None
    target: Target


class ClipsEngine:
    """A rule engine on CLIPS. See the module docstring for what one fire does."""

    def __init__(self, *, max_firings: int = 10_000, strict: bool = False) -> None:
        """``strict``: ``set`` refuses variables never declared (engines built from a model are strict)."""
        self.strict = strict
        self._faults = Faults()
        self._ops = Operations()
        self._bridge = Bridge()
        self._variables: dict[str, _Variable] = {}
        self._by_member: dict[str, list[str]] = {}
        self._values: list[Value] = [None]  # 1-based, like the CLIPS dispatcher
        self._globals: list[str] = [""]
        self._dirty: dict[int, Value] = {}
        self._stale = False
        self._pusher_count = 0
        self._rulesets = RuleSets(self._bridge, self._target_for, self._ops.number_for)
        self._sets = self._rulesets.sets
        self._bridge.build(put_dispatcher([]))
        self._bridge.build(assign_dispatcher([], []))
        self._bridge.build(RUN)
        self._bridge.build(FIRE)
        self.max_firings = max_firings

    @property
    def error_count(self) -> int:
        """Faults met while firing (evaluation errors, unbound or raising operations, CLIPS errors)."""
        return self._faults.count

    @property
    def errors(self) -> deque[FireError]:
        """The last 100 faults, oldest first (clear it at will)."""
        return self._faults.recent

    @property
    def max_firings(self) -> int:
        """Rule firings one fire may run before it stops (only native rules can need many)."""
        return self._max_firings

    @max_firings.setter
    def max_firings(self, limit: int) -> None:
        if not isinstance(limit, int) or limit < 1:
            raise ValueError(f"max_firings must be a positive integer, not {limit!r}")
        self._bridge.run(f"(bind ?*acord-limit* {limit})")
        self._max_firings = limit

    # --------------------------------------------------------------------------- declarations
    def declare(self, variable: str, initial: object = None, *, type: str | None = None) -> None:
        """Declare a variable (``Element.attribute``), optionally typed (``int``, ``double``, ``string``,
        ``bool``... or ``number``/``string``/``boolean``) and with an initial value."""
        if not isinstance(variable, str) or not _VARIABLE.match(variable):
            raise RuleError(
                f"{variable!r} is not a variable name; write Element.attribute (letters, digits, _)"
            )
        kind = kind_of_type(type)
        existing = self._variables.get(variable)
        if existing is None:
            index = len(self._values)
            existing = _Variable(variable, index, kind, Target(index, f"?*{variable}*"))
            try:
                self._bridge.build(
                    f"(defglobal MAIN {existing.target.global_name} = nil ?*acord-vf{index}* = FALSE)"
                )
                self._bridge.run(f"(bind ?*acord-vf{index}* (assert (acord-var (i {index}))))")
            except ClipsFailure as err:
                raise RuleError(f"CLIPS cannot hold variable {variable!r}: {err}") from None
            self._variables[variable] = existing
            self._by_member.setdefault(variable.rpartition(".")[2], []).append(variable)
            self._values.append(None)
            self._globals.append(existing.target.global_name)
            self._stale = True
        else:
            existing.kind = kind
        if initial is not None:
            self.set(variable, initial)

    def declare_operation(
        self, name: str, parameters: tuple[str, ...] | list[str] | None = None
    ) -> None:
        """Declare an operation (``Element.operation``) rules may call. Once any is declared, a rule
        calling an undeclared operation, or with the wrong number of arguments, is refused."""
        if not isinstance(name, str) or not _VARIABLE.match(name):
            raise RuleError(f"{name!r} is not an operation name; write Element.operation")
        self._ops.declare(name, None if parameters is None else tuple(parameters))

    def bind(self, element: str, obj: object) -> None:
        """Operations ``element.op(...)`` called by rules run ``obj.op(...)``."""
        self._ops.bind(element, obj)

    def bind_operation(self, name: str, function: Callable[..., object]) -> None:
        """Operation ``name`` (``Element.operation``) called by rules runs ``function``."""
        if not callable(function):
            raise TypeError(
                f"bind_operation({name!r}, ...) needs a callable, not {type(function).__name__}"
            )
        self._ops.bind_function(name, function)

    # ------------------------------------------------------------------------ the four calls
    def defrule(self, rule: str, ruleset: str) -> str:
        """Add ``rule`` (crisp syntax, or native CLIPS ``(defrule ...)`` text) to ``ruleset``, or
        replace the rule with the same label there. Returns the label."""
        if not isinstance(rule, str) or not rule.strip():
            raise RuleError(
                "the rule is empty; write 'label: if ... then ...' or (defrule ...)",
                ruleset=str(ruleset),
            )
        return self._rulesets.define(rule, ruleset)

    def set(self, variable: str, value: object) -> None:
        """Set a variable's value; it reaches CLIPS with the next ``fire``."""
        var = self._variables.get(variable) if type(variable) is str else None
        if (
            var is not None
            and type(value) is float
            and var.kind != "string"
            and var.kind != "boolean"
        ):
            self._values[var.index] = self._dirty[var.index] = value  # the monitor's hot path
            return
        if var is None:
            var = self._lookup_for_set(variable)
        try:
            clean = normalise(value, var.kind)
        except ValueError as err:
            raise RuleError(f"cannot set {var.name} to {value!r}: {err}") from None
        self._values[var.index] = clean
        self._dirty[var.index] = clean

    def fire(self, ruleset: str) -> None:
        """Fire the rules of ``ruleset`` on the current values (see the module docstring)."""
        target = self._sets.get(ruleset)
        if target is None:
            known = ", ".join(sorted(self._sets)) or "none yet"
            raise RuleError(
                f"no rule set {ruleset!r} (known: {known}); define its rules with defrule first"
            )
        if self._stale:
            self._rebuild_dispatchers()
        function, args = self._push_call(target)
        try:
            out = self._bridge.call(function, args)
        except ClipsFailure as err:
            out = self._recover(target, str(err))
        else:
            printed = self._bridge.messages() if self._bridge.captured else ""
            if type(out) is not tuple:  # a native rule's error halted the run before it returned
                out = self._recover(target, printed or "the run was halted")
            elif printed:
                self._faults.add(target.name, None, f"CLIPS reported: {printed}")
        if out:
            self._apply(target, out)

    def get(self, variable: str) -> Value:
        """The current value of a variable (None if never set)."""
        found = self._variables.get(variable) if isinstance(variable, str) else None
        if found is not None:
            return self._values[found.index]
        if not isinstance(variable, str):
            raise RuleError(f"{variable!r} is not a variable name; write Element.attribute")
        try:
            return self._values[self._lookup(variable).index]
        except LookupError as err:
            raise RuleError(str(err.args[0])) from None

    # ------------------------------------------------------------------------------ inspection
    def rules(self, ruleset: str) -> list[str]:
        """Labels of a rule set's rules, in definition order."""
        target = self._rulesets.sets.get(ruleset)
        return list(target.rules) if target else []

    def construct(self, ruleset: str, label: str) -> str:
        """The CLIPS text a rule was built from (what a crisp rule compiled to)."""
        return self._rulesets.sets[ruleset].rules[label].constructs[-1]

    # -------------------------------------------------------------------------------- internals
    def _lookup(self, text: str) -> _Variable:
        found = self._variables.get(text)
        if found is not None:
            return found
        candidates = self._by_member.get(text, []) if "." not in text else []
        if len(candidates) == 1:
            return self._variables[candidates[0]]
        if candidates:
            raise LookupError(
                f"variable {text!r} is ambiguous ({', '.join(candidates)}); write Element.{text}"
            )
        close = difflib.get_close_matches(text, list(self._variables), n=3)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        if self.strict:
            todo = (
                "use an attribute of an element in the policy set's scope, or add it to the model"
            )
        else:
            todo = f"declare it with engine.declare({text!r}, initial) or set it first"
        raise LookupError(f"unknown variable {text!r}{hint}; {todo}")

    def _lookup_for_set(self, variable: str) -> _Variable:
        found = self._variables.get(variable) if isinstance(variable, str) else None
        if found is not None:
            return found
        if not isinstance(variable, str) or not _VARIABLE.match(variable):
            raise RuleError(f"{variable!r} is not a variable name; write Element.attribute")
        try:
            return self._lookup(variable)
        except LookupError as err:
            if self.strict:
                raise RuleError(str(err.args[0])) from None
        self.declare(variable)
        return self._variables[variable]

    def _target_for(self, name: Name) -> Target:
        return self._lookup(name.text).target

    def _rebuild_dispatchers(self) -> None:
        names = list(self._variables)
        targets = [self._variables[n].target for n in names]
        self._bridge.build(put_dispatcher([t.global_name for t in targets]))
        self._bridge.build(assign_dispatcher(names, targets))
        self._stale = False

    def _push_call(self, target: RuleSet) -> tuple[bytes, list[object]]:
        """The one call of a fire: a push function made for this (set, changed variables) pattern,
        taking just the values; past _MAX_PUSHERS patterns, the generic (index, value) pairs."""
        dirty = self._dirty
        key = tuple(dirty)
        function = target.pushers.get(key)
        if function is None and self._pusher_count < _MAX_PUSHERS:
            self._pusher_count += 1
            name = f"acord-push{self._pusher_count}"
            globals_ = [self._globals[i] for i in key]
            try:
                self._bridge.build(pusher(name, target.name, target.natives, globals_))
            except (
                ClipsFailure
            ) as err:  # cannot happen with valid names; the generic path still works
                self._faults.add(target.name, None, f"push function not built: {err}")
            else:
                function = target.pushers[key] = name.encode()
        if function is not None:
            args: list[object] = list(dirty.values())
        else:
            function, args = b"acord-fire-set", [target.symbol, target.natives]
            for pair in dirty.items():
                args.extend(pair)
        dirty.clear()
        return function, args

    def _recover(self, target: RuleSet, message: str) -> tuple:
        self._faults.add(target.name, None, f"CLIPS error while firing: {message}")
        try:
            out = self._bridge.value_of("acord-out")
            self._bridge.call(b"acord-cleanup", [])
        except ClipsFailure:
            out = ()
        self._bridge.messages()
        # Whatever was pushed may not have arrived: push everything with the next fire.
        self._dirty = {i: self._values[i] for i in range(1, len(self._values))}
        return out if isinstance(out, tuple) else ()

    def _apply(self, target: RuleSet, out: tuple) -> None:
        """Records from CLIPS, in firing order: assignments first, then the operations called."""
        values, labels = self._values, self._rulesets.labels
        calls: list[tuple[int | str, object, tuple]] = []
        i, n = 0, len(out)
        while i < n:
            tag = out[i]
            if type(tag) is int and tag > 0:
                values[tag] = from_clips(out[i + 1])
                i += 2
            elif type(tag) is int and tag < 0:
                count = out[i + 2]
                calls.append((-tag, out[i + 1], out[i + 3 : i + 3 + count]))
                i += 3 + count
            elif tag == "err":
                self._faults.add(target.name, labels.get(out[i + 1]), self._describe(out[i + 2]))
                i += 3
            elif tag == "op":
                count = out[i + 2]
                calls.append((str(out[i + 1]), 0, out[i + 3 : i + 3 + count]))
                i += 3 + count
            else:
                message = (
                    f"unreadable record {tag!r} from CLIPS; did a native rule bind ?*acord-out*?"
                )
                self._faults.add(target.name, None, message)
                break
        for op, rule, args in calls:
            self._ops.invoke(op, args, target.name, labels.get(rule), self._faults)

    def _describe(self, message: object) -> str:
        if message == "limit":
            return (
                f"stopped after {self.max_firings} rule firings without settling; pending activations were"
                " dropped (does a native rule re-activate itself?)"
            )
        return str(message)
