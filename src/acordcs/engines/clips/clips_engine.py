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

Numeric mode, a matter of speed only: a crisp condition that reads only variables declared as
numbers (``type="double"``...) and number literals, with no division, is compiled twice, checked
and unchecked; CLIPS takes the unchecked branch while its flag ``?*acord-num*`` is TRUE, which the
engine keeps so only while every numeric variable holds a number (not unset, not given a string by
a rule). A native rule, or a variable whose declared type changes, turns it off for good: either
could put anything in a numeric variable without the engine knowing.
"""

from __future__ import annotations

import difflib
import re
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from acordcs.engines.clips.bridge import MULTIFIELD, Bridge, ClipsFailure
from acordcs.engines.clips.clips_compiler import Target
from acordcs.engines.clips.prelude import (
    FIRE,
    NUMERIC_FLAG,
    RUN,
    assign_dispatcher,
    fixed_constructs,
    pusher,
    put_dispatcher,
)
from acordcs.engines.clips.program import ProgramVariable, program_text
from acordcs.engines.clips.records import decode
from acordcs.engines.clips.rule_calls import Faults, FireError, OperationTable
from acordcs.engines.clips.rulesets import RuleSet, RuleSets
from acordcs.engines.clips.values import Value, kind_of_type, normalise, shown
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import Name

__all__ = ["ClipsEngine", "FireError"]

_VARIABLE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*\Z")
_MAX_PUSHERS = 256  # distinct (rule set, variables set) patterns with their own push function


@dataclass(slots=True)
class _Variable:
    name: str
    index: int
    kind: str | None
    target: Target
    # set's hot path stores a float as it is: untyped, or numeric and already holding a number
    floats: bool = False
    type_name: str = ""  # as declared (the model's type), for program()


class ClipsEngine:
    """A rule engine on CLIPS. See the module docstring for what one fire does."""

    def __init__(self, *, max_firings: int = 10_000, strict: bool = False) -> None:
        """``strict``: ``set`` refuses variables never declared (engines built from a model are strict)."""
        self.strict = strict
        self._faults = Faults()
        self._ops = OperationTable()
        self._bridge = Bridge(fixed_constructs())
        self._variables: dict[str, _Variable] = {}
        self._names: list[str] = [""]  # by number
        self._by_member: dict[str, list[str]] = {}
        self._bound: dict[str, str] = {}  # names as rules write them -> declared (bind_names)
        # 1-based, like the CLIPS dispatcher; number 0 is the numeric-mode flag (_sync_numeric)
        self._values: list[Value] = [False]
        self._globals: list[str] = [NUMERIC_FLAG]
        self._dirty: dict[int, Value] = {}
        # Numeric mode: crisp conditions reading only variables declared as numbers run without
        # type checks while CLIPS's flag is TRUE, which it is only while each of those variables
        # holds a number. _odd: the numeric variables that do not (unset, or given another value
        # by a rule); _flag: what the flag is in CLIPS after the next push; _numeric_ok: False for
        # good once something could write a numeric variable unseen (a native rule, a type change).
        self._odd: set[int] = set()
        self._numeric: set[int] = set()  # the variables declared as numbers
        self._flag = False
        self._numeric_ok = True
        self._stale = False
        self._pusher_count = 0
        self._rulesets = RuleSets(self._bridge, self._target_for, self._ops.number_for)
        self._sets = self._rulesets.sets
        self._sites = self._rulesets.sites.entries  # the same list, grown by each defrule
        self._ptr = self._bridge.ptr
        self._bridge.build(put_dispatcher(self._globals))
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
                # Its acord-var fact is asserted when a rule first reads it (RuleSets.define_crisp).
                self._bridge.build(
                    f"(defglobal MAIN {existing.target.global_name} = nil ?*acord-vf{index}* = FALSE)"
                )
            except ClipsFailure as err:
                raise RuleError(f"CLIPS cannot hold variable {variable!r}: {err}") from None
            self._variables[variable] = existing
            existing.type_name = type or ""
            self._names.append(variable)
            self._by_member.setdefault(variable.rpartition(".")[2], []).append(variable)
            self._values.append(None)
            self._globals.append(existing.target.global_name)
            self._stale = True
            existing.floats = kind is None
            if kind == "number":
                self._numeric.add(index)
                self._odd.add(index)  # unset until a number is set
        elif existing.kind != kind:
            # Rules compiled before may write it without the check a numeric variable needs.
            self._numeric_ok = False
            self._numeric.discard(existing.index)
            self._odd.discard(existing.index)
            existing.kind = kind
            existing.floats = kind in (None, "number")  # untracked from now on
        self._sync_numeric()
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

    def bind_names(
        self, variables: Mapping[str, str], operations: Mapping[str, str] | None = None
    ) -> None:
        """Bind names as rules write them to declared variables and operations (``retries`` ->
        ``Recovery.retries``): a policy set's resolution (:mod:`acordcs.engines.plan`), used before
        the engine's own lookup (a declared name, or the one ``X.name``)."""
        unknown = sorted(v for v in variables.values() if v not in self._variables)
        unknown += sorted(o for o in (operations or {}).values() if o not in self._ops.declared)
        if unknown:
            raise RuleError(f"cannot bind names to undeclared ones: {', '.join(unknown)}")
        self._bound.update(variables)
        self._ops.aliases.update(operations or {})

    def define_ruleset(self, ruleset: str) -> None:
        """Create an empty rule set (``defrule`` creates one on demand)."""
        self._rulesets.ensure(ruleset)

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
    def defrule(self, rule: str, ruleset: str, *, priority: int | None = None) -> str:
        """Add ``rule`` (crisp syntax, or native CLIPS ``(defrule ...)`` text) to ``ruleset``, or
        replace the rule with the same label there. Returns the label. ``priority``: a crisp
        rule's 1-based rank among the set's rules (default: after those defined so far)."""
        if not isinstance(rule, str) or not rule.strip():
            raise RuleError(
                "the rule is empty; write 'label: if ... then ...' or (defrule ...)",
                ruleset=str(ruleset),
            )
        label = self._rulesets.define(rule, ruleset, priority)
        if self._numeric_ok and self._sets[ruleset].natives:
            # A native rule may bind any global: numeric mode can no longer be sure of anything.
            self._numeric_ok = False
            self._sync_numeric()
        return label

    def set(self, variable: str, value: object) -> None:
        """Set a variable's value; it reaches CLIPS with the next ``fire``."""
        try:
            var = self._variables[variable]
        except (KeyError, TypeError):  # not a declared name (or not even hashable)
            var = self._lookup_for_set(variable)
        else:
            if type(value) is float and var.floats:  # the monitor's hot path: nothing to check
                index = var.index
                self._values[index] = self._dirty[index] = value
                return
        try:
            clean = normalise(value, var.kind)
        except ValueError as err:
            raise RuleError(f"cannot set {var.name} to {shown(value)}: {err}") from None
        self._values[var.index] = clean
        self._dirty[var.index] = clean
        if var.index in self._numeric:
            self._track(var.index, clean)

    def fire(self, ruleset: str) -> None:
        """Fire the rules of ``ruleset`` on the current values (see the module docstring)."""
        try:
            target = self._sets[ruleset]
        except (KeyError, TypeError):
            known = ", ".join(sorted(self._sets)) or "none yet"
            raise RuleError(
                f"no rule set {ruleset!r} (known: {known}); define its rules with defrule first"
            ) from None
        if self._stale:
            self._rebuild_dispatchers()
        dirty = self._dirty
        function = target.pushers.get(tuple(dirty))
        if function is None:
            function, args = self._push_call(target)
        else:  # the usual case: this pattern's push function takes the values, in dirty's order
            args = dirty.values()
        bridge = self._bridge
        try:
            result = bridge.call(function, args)
        except ClipsFailure as err:
            self._recover(target, str(err))
            return
        dirty.clear()
        if bridge.capture.text:
            printed = bridge.messages()
            if result.header.type != MULTIFIELD:  # a native rule's error halted the run
                self._recover(target, printed or "the run was halted")
                return
            self._faults.add(target.name, None, f"CLIPS reported: {printed}")
        elif result.header.type != MULTIFIELD:
            self._recover(target, "the run was halted")
            return
        multifield = result.multifieldValue
        if multifield.length:
            self._apply(target, multifield)

    def get(self, variable: str) -> Value:
        """The current value of a variable (None if never set)."""
        try:
            return self._values[self._variables[variable].index]
        except (KeyError, TypeError):
            pass
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

    def explain(self, ruleset: str) -> dict[str, float]:
        """Per rule of ``ruleset`` (definition order): 1.0 if it fired in the engine's last fire,
        0.0 if not. Meaningful right after ``fire(ruleset)``: each fire starts a new cycle, so a
        fire of another rule set of this engine leaves every rule here at 0.0. A native rule is
        always 0.0 (CLIPS keeps no record of its firings that we read)."""
        target = self._rulesets.sets.get(ruleset)
        if target is None:
            raise RuleError(f"no rule set {ruleset!r}; define its rules with defrule first")
        crisp = [e for e in target.rules.values() if e.kind == "crisp" and e.rule_id]
        fired: set[str] = set()
        if crisp:
            # One evaluation for the whole set: the cycle, then each rule's "fired" global.
            globals_ = " ".join(f"?*acord-f{e.rule_id}*" for e in crisp)
            values = self._bridge.env.eval(f"(create$ ?*acord-cycle* {globals_})")
            cycle = values[0]
            # Before the first fire the cycle and every global are 0: nothing fired yet.
            fired = (
                set()
                if cycle == 0
                else {e.label for e, v in zip(crisp, values[1:], strict=True) if v == cycle}
            )
        return {label: 1.0 if label in fired else 0.0 for label in target.rules}

    def construct(self, ruleset: str, label: str) -> str:
        """The CLIPS text a rule was built from (what a crisp rule compiled to)."""
        return self._rulesets.sets[ruleset].rules[label].constructs[-1]

    def program(self) -> str:
        """The engine as one CLIPS program text, for another CLIPS to load (see
        :func:`acordcs.engines.clips.program.program_text`)."""
        variables = [
            ProgramVariable(v.name, v.index, v.target, self._values[v.index], v.type_name)
            for v in self._variables.values()
        ]
        sets = self._rulesets.sets.values()
        return program_text(
            variables,
            [(rs.name, [e.constructs for e in rs.rules.values()]) for rs in sets],
            sites=self._rulesets.sites.entries,
            rule_labels={
                e.rule_id: f"{rs.name}::{e.label}" for rs in sets for e in rs.rules.values()
            },
            operations=self._ops.names(),
            read=sorted(self._rulesets.read),
        )

    # -------------------------------------------------------------------------------- internals
    def _lookup(self, text: str) -> _Variable:
        found = self._variables.get(self._bound.get(text, text))
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
        var = self._lookup(name.text)
        if self._numeric_ok and var.kind == "number":  # the compiler may leave its checks out
            return Target(var.index, var.target.global_name, numeric=True)
        return var.target

    def _track(self, index: int, value: Value) -> None:
        """A numeric variable got ``value``: keep ``_odd`` and the flag in step."""
        var = self._variables[self._names[index]]
        if type(value) is float or type(value) is int:
            self._odd.discard(index)
            var.floats = True  # set's hot path may store floats again, unchecked
        else:
            self._odd.add(index)
            var.floats = False
        self._sync_numeric()

    def _sync_numeric(self) -> None:
        """Push the flag with the next fire if what it should be changed (``_flag``: what CLIPS
        holds once the changed values are pushed)."""
        flag = self._numeric_ok and not self._odd
        if flag != self._flag:
            self._flag = self._values[0] = self._dirty[0] = flag

    def _rebuild_dispatchers(self) -> None:
        names = list(self._variables)
        targets = [self._variables[n].target for n in names]
        self._bridge.build(put_dispatcher(self._globals))
        self._bridge.build(assign_dispatcher(names, targets))
        self._stale = False

    def _push_call(self, target: RuleSet) -> tuple[bytes, list[object]]:
        """The one call of a fire, when the pattern of changed variables has no push function yet:
        make one, taking just the values; past _MAX_PUSHERS patterns, the generic (index, value)
        pairs. Clears the changed values (they are in the arguments)."""
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

    def _recover(self, target: RuleSet, message: str) -> None:
        self._faults.add(target.name, None, f"CLIPS error while firing: {message}")
        try:  # acord-cleanup returns the records of what happened before the error: they stand
            result = self._bridge.call(b"acord-cleanup", [])
        except ClipsFailure:
            result = None
        self._bridge.messages()
        # Whatever was pushed may not have arrived: push everything with the next fire.
        self._dirty = dict(enumerate(self._values))
        if result is not None and result.header.type == MULTIFIELD:
            self._apply(target, result.multifieldValue)

    def _apply(self, target: RuleSet, multifield: object) -> None:
        """Records from CLIPS, in firing order: assignments first, then the operations called."""
        calls, notes = decode(
            multifield, self._ptr, self._sites, self._values, self._numeric, self._odd
        )
        if notes is None and calls is None:
            return
        labels = self._rulesets.labels
        for what, number, value in notes or ():
            if what == "set":
                if type(value) is not float and type(value) is not int:
                    # A crisp rule's assignment cleared the flag in CLIPS (compiler.numeric_check):
                    # that is what CLIPS holds now, whatever an earlier note meant to push.
                    self._dirty.pop(0, None)
                    self._flag = self._values[0] = False
                self._track(number, value)
            else:
                self._faults.add(target.name, labels.get(number), self._describe(value))
        for op, rule, args in calls or ():
            self._ops.invoke(op, args, target.name, labels.get(rule), self._faults)

    def _describe(self, message: object) -> str:
        if message == "limit":
            return (
                f"stopped after {self.max_firings} rule firings without settling; pending activations were"
                " dropped (does a native rule re-activate itself?)"
            )
        return str(message)
