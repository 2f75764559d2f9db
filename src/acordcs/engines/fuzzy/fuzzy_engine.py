"""The fuzzy rule engine behind the paper's four calls: ``defrule``, ``set``, ``fire``, ``get``.

Variables are declared first (:meth:`FuzzyEngine.define_variable`, or from a model or an FCL file);
they are shared by all rule sets of the engine, so one rule set's output can be another's input.
Values:

- ``set`` rejects NaN and infinities with :class:`RuleError` (the variable keeps its value) and
  clamps a value outside the variable's range into it, logging a warning once per variable;
- ``fire`` never raises for data: an output for which no rule fired takes its DEFAULT (or keeps its
  value, see :class:`~acordcs.engines.fuzzy.variable.LinguisticVariable`); :meth:`FuzzyEngine.defaulted`
  says which outputs did so in the last fire of a rule set.
"""

from __future__ import annotations

import logging
import math
import re
from collections.abc import Mapping
from numbers import Real

import numpy as np

from acordcs.engines.fuzzy.fuzzy_compiler import (
    CompiledRuleSet,
    OutputPlan,
    RuleEntry,
    compile_ruleset,
    output_plan,
    resolve_name,
    resolve_rule,
    unknown_variable_message,
)
from acordcs.engines.fuzzy.semantics import Semantics, connect, resolve
from acordcs.engines.fuzzy.variable import LinguisticVariable, TermsSpec, build_variable
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import Rule, RuleSyntaxError, parse_rule
from acordcs.rules.binding import default_label

log = logging.getLogger("acordcs.engines.fuzzy")
_LABEL = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*:(?!=)")


class FuzzyEngine:
    """A fuzzy rule engine implementing :class:`acordcs.engines.rule_engine.RuleEngine`.

    ``semantics``: ``"mamdani"`` (default), ``"sazonov"``, ``"fcl"`` or a :class:`Semantics`; it is
    the default for rule sets created by ``defrule``; :meth:`define_ruleset` chooses per rule set.
    """

    def __init__(self, semantics: str | Semantics = "mamdani", *, name: str | None = None) -> None:
        self.semantics = resolve(semantics)
        self.name = name
        self._vars: dict[str, LinguisticVariable] = {}
        self._values: dict[str, float | None] = {}
        self._alias: dict[str, str] = {}
        # Names bound by the model (bind_names): how its rules write each variable.
        self._bound: dict[str, str] = {}
        self._sets: dict[str, dict[str, RuleEntry]] = {}
        self._set_semantics: dict[str, Semantics] = {}
        self._compiled: dict[str, CompiledRuleSet] = {}
        self._defaulted: dict[str, tuple[str, ...]] = {}
        self._warned: set[str] = set()
        # Output plans by (rule set, output, semantics), for the variable object they were built
        # from: building one costs about as much as its terms (250 terms: 4 ms), so building it
        # for every rule made reading a rule base cubic (250 one-rule terms: 75 s).
        self._plans: dict[tuple[str, str, Semantics], tuple[LinguisticVariable, OutputPlan]] = {}

    # ------------------------------------------------------------------------------ declaring
    def define_variable(
        self,
        name: str,
        lo: float,
        hi: float,
        terms: TermsSpec = None,
        *,
        default: float | None = None,
        keep_last: bool = False,
        method: str | None = None,
        initial: float | None = None,
    ) -> LinguisticVariable:
        """Declare (or redeclare) a linguistic variable.

        ``terms``: FCL-style text (``"slow := trape 0 0 40 80; fast := trian 60 200 200"``), a list of
        :class:`~acordcs.rules.parser.TermDef`, or a mapping of names to Memberships. Redeclaring
        a variable re-checks every rule that uses it; nothing changes if one no longer fits.
        """
        var = build_variable(
            name,
            lo,
            hi,
            terms,
            default=default,
            keep_last=keep_last,
            method=method,
            initial=initial,
        )
        if name in self._vars:
            trial = dict(self._vars)
            trial[name] = var
            for ruleset, entries in self._sets.items():
                sem = self.semantics_of(ruleset)
                for entry in entries.values():
                    resolve_rule(
                        entry.rule,
                        entry.label,
                        ruleset,
                        trial,
                        file=entry.file,
                        line=entry.line,
                        names=self._bound,
                    )
                    if name in (v for v, _ in entry.consequents):
                        self._plan(ruleset, var, sem)
        self._vars[name] = var
        current = self._values.get(name)
        if current is not None:
            current = min(max(current, var.lo), var.hi)
        self._values[name] = current if current is not None else var.initial
        self._alias.clear()
        self._compiled.clear()
        return var

    def bind_names(self, names: Mapping[str, str]) -> None:
        """Bind names as rules write them to declared variables (``cycleRate`` ->
        ``Control.cycleRate``): a policy set's resolution (:mod:`acordcs.engines.plan`), used
        before the engine's own lookup (a declared name, or the one ``X.name``)."""
        unknown = sorted(v for v in names.values() if v not in self._vars)
        if unknown:
            raise RuleError(f"cannot bind names to undeclared variables: {', '.join(unknown)}")
        self._bound.update(names)
        self._alias.clear()

    def define_ruleset(self, ruleset: str, semantics: str | Semantics | None = None) -> None:
        """Create an empty rule set (or change its semantics); ``defrule`` creates one on demand."""
        sem = resolve(semantics) if semantics is not None else self.semantics
        self._sets.setdefault(ruleset, {})
        self._set_semantics[ruleset] = sem
        for var in {v for e in self._sets[ruleset].values() for v, _ in e.consequents}:
            self._plan(ruleset, self._vars[var], sem)
        self._compiled.pop(ruleset, None)

    # ------------------------------------------------------------------------------ the four calls
    def defrule(self, rule: str, ruleset: str) -> str:
        """Add ``rule`` (the paper's syntax) to ``ruleset``, or replace the rule with its label.

        An unlabelled rule gets ``rule<n>``, n being its 1-based position in the set (the first free
        such label): stable across runs that define the same rules in the same order.
        """
        if not isinstance(rule, str):
            raise RuleError(f"a rule is text, got {type(rule).__name__}", ruleset=ruleset)
        try:
            parsed = parse_rule(rule.strip(), "fuzzy")
        except RuleSyntaxError as exc:
            m = _LABEL.match(rule)
            label = m.group(1) if m else f"#{len(self._sets.get(ruleset, {})) + 1}"
            raise RuleError(exc.message, ruleset=ruleset, rule=label, column=exc.column) from None
        return self.add_rule(parsed, ruleset)

    def add_rule(
        self, rule: Rule, ruleset: str, *, file: str | None = None, line: int | None = None
    ) -> str:
        """Add an already parsed rule (an FCL reader uses this); same contract as :meth:`defrule`."""
        entries = self._sets.get(ruleset, {})
        label = rule.label or self._free_label(entries)
        entry = resolve_rule(
            rule, label, ruleset, self._vars, file=file, line=line, names=self._bound
        )
        sem = self._set_semantics.get(ruleset, self.semantics)
        for var, _ in entry.consequents:
            try:
                self._plan(ruleset, self._vars[var], sem)
            except RuleError as exc:
                raise RuleError(
                    exc.message, ruleset=ruleset, rule=label, file=file, line=line
                ) from None
        self._sets.setdefault(ruleset, {})[label] = entry
        self._set_semantics.setdefault(ruleset, sem)
        self._compiled.pop(ruleset, None)
        return label

    def remove_rule(self, label: str, ruleset: str) -> None:
        """Remove a rule by label (RuleError if there is none)."""
        entries = self._sets.get(ruleset)
        if not entries or label not in entries:
            raise RuleError(f"no rule {label!r} in rule set {ruleset!r}", ruleset=ruleset)
        del entries[label]
        self._compiled.pop(ruleset, None)

    def set(self, variable: str, value: object) -> None:
        """Give a variable a value: a number (text, or a number too large for a float, NaN or
        infinity: RuleError and the variable keeps its value; outside the range: clamped, warned
        once)."""
        name = self._alias.get(variable) or self._canonical(variable)
        if type(value) is float:  # the hot path: monitors and policy sets feed floats
            x = value
        elif isinstance(value, Real):  # int, bool, numpy numbers, Fraction; never text
            try:
                x = float(value)
            except OverflowError:
                raise RuleError(
                    f"value for {variable!r} is beyond a float's range (about 1.8e308); "
                    f"the variable keeps {self._values[name]!r}"
                ) from None
        else:
            shown = repr(value)
            shown = shown if len(shown) <= 40 else shown[:37] + "..."
            raise RuleError(
                f"value for {variable!r} must be a number, got {type(value).__name__} {shown}; "
                f"the variable keeps {self._values[name]!r}"
            )
        var = self._vars[name]
        if not var.lo <= x <= var.hi:
            if not math.isfinite(x):
                raise RuleError(
                    f"value {x!r} for {variable!r} is not a finite number; "
                    f"the variable keeps {self._values[name]!r}. Check the sensor or monitor feeding it"
                )
            self._warn_clamp(name, x)
            x = var.lo if x < var.lo else var.hi
        self._values[name] = x

    def fire(self, ruleset: str) -> None:
        """Fire the rules of ``ruleset`` on the current values; outputs get new values."""
        compiled = self._compiled.get(ruleset) or self._compile(ruleset)
        self._defaulted[ruleset] = compiled.run(self._values)

    def get(self, variable: str) -> float:
        """The current value of a variable: its DEFAULT if it never had one and has a DEFAULT, else
        RuleError if it never had one."""
        name = self._alias.get(variable) or self._canonical(variable)
        value = self._values[name]
        if value is None and self._vars[name].default is not None:
            # an output no fire has concluded yet reads as its DEFAULT (jFuzzyLogic's value for
            # an output no rule concludes)
            return self._vars[name].default  # type: ignore[return-value]
        if value is None:
            raise RuleError(
                f"variable {variable!r} has no value yet; set it, or fire a rule set that concludes it"
            )
        return value

    # ------------------------------------------------------------------------------ more
    def batch(self, ruleset: str, inputs: Mapping[str, object]) -> dict[str, np.ndarray]:
        """Evaluate ``ruleset`` on many input vectors at once; the engine's values do not change.

        ``inputs`` maps variable names to equal-length arrays (a scalar is broadcast; an input not
        given uses its current value; a declared variable that is not an input is ignored). Returns one array per output, equal to what ``set``/``fire``/
        ``get`` would give row by row. NaN/inf raise RuleError naming the first bad row.
        """
        from acordcs.engines.fuzzy.batch import run_batch

        compiled = self._compiled.get(ruleset) or self._compile(ruleset)
        columns: dict[str, object] = {}
        for written, column in inputs.items():
            name = self._canonical(written)
            columns[name] = column
        return run_batch(compiled, columns, self._values, self._warn_clamp)

    def explain(self, ruleset: str, values: Mapping[str, object] | None = None) -> dict[str, float]:
        """Each rule's firing strength in ``ruleset`` (label -> degree in 0..1, definition order):
        its condition's degree under the rule set's AND/OR, times its weight. On ``values``
        (variable -> number, missing ones from the engine's current values) or on the current
        values; a rule reading an input without a value gives 0 (it could not fire). Read-only: nothing fires, no value changes.
        Evaluated with an explicit stack, so a rule nested arbitrarily deep cannot recurse."""
        entries = self.rules(ruleset)
        sem = self.semantics_of(ruleset)
        current: dict[str, float | None] = dict(self._values)
        for written, value in (values or {}).items():
            name = self._canonical(written)
            if isinstance(value, Real) and math.isfinite(float(value)):
                var = self._vars[name]
                current[name] = min(max(float(value), var.lo), var.hi)
        return {
            e.label: 0.0
            if any(current.get(v) is None for v in e.inputs())
            else _degree(e.condition, self._vars, current, sem) * e.weight
            for e in entries
        }

    def defaulted(self, ruleset: str) -> tuple[str, ...]:
        """Outputs that took their DEFAULT (no rule fired for them) in the last fire of ``ruleset``."""
        return self._defaulted.get(ruleset, ())

    @property
    def variables(self) -> dict[str, LinguisticVariable]:
        return dict(self._vars)

    def rulesets(self) -> list[str]:
        return list(self._sets)

    def rules(self, ruleset: str) -> list[RuleEntry]:
        """The rules of a rule set, in definition order."""
        if ruleset not in self._sets:
            raise RuleError(
                f"no rule set {ruleset!r} (rule sets: {', '.join(self._sets) or 'none'})"
            )
        return list(self._sets[ruleset].values())

    def semantics_of(self, ruleset: str) -> Semantics:
        return self._set_semantics.get(ruleset, self.semantics)

    # ------------------------------------------------------------------------------ internals

    def _canonical(self, written: str) -> str:
        found = self._bound.get(written) or resolve_name(self._vars, written)
        if isinstance(found, list):
            if len(found) != 1:
                raise RuleError(unknown_variable_message(self._vars, written, found))
            found = found[0]
        self._alias[written] = found
        return found

    def _compile(self, ruleset: str) -> CompiledRuleSet:
        entries = self._sets.get(ruleset)
        if entries is None:
            raise RuleError(
                f"no rule set {ruleset!r} (rule sets: {', '.join(self._sets) or 'none'}); defrule first",
                ruleset=ruleset,
            )
        compiled = compile_ruleset(
            ruleset, list(entries.values()), self._vars, self.semantics_of(ruleset), self._plan
        )
        self._compiled[ruleset] = compiled
        return compiled

    def _plan(self, ruleset: str, var: LinguisticVariable, sem: Semantics) -> OutputPlan:
        """The output plan of ``var`` in ``ruleset``, built once per variable object and semantics."""
        key = (ruleset, var.name, sem)
        found = self._plans.get(key)
        if found is not None and found[0] is var:
            return found[1]
        plan = output_plan(ruleset, var, sem)
        self._plans[key] = (var, plan)
        return plan

    def _warn_clamp(self, name: str, x: float) -> None:
        if name in self._warned:
            return
        self._warned.add(name)
        var = self._vars[name]
        log.warning(
            "value %s for %r is outside its range %s; clamped into it (said once per variable)",
            x,
            name,
            var.describe_range(),
        )

    def _free_label(self, entries: Mapping[str, RuleEntry]) -> str:
        return default_label(len(entries) + 1, entries)


def _combine(op: str, a: float, b: float) -> float:
    return connect(op, a, b)


def _degree(
    condition: tuple,
    variables: Mapping[str, LinguisticVariable],
    values: Mapping[str, float | None],
    sem: Semantics,
) -> float:
    """A resolved condition's degree (see RuleEntry), post-order with an explicit stack."""
    stack: list[tuple[tuple, bool]] = [(condition, False)]
    results: list[float] = []
    while stack:
        node, expanded = stack.pop()
        kind = node[0]
        if kind == "is":
            _, name, hedges, term = node
            x = values.get(name)
            mu = 0.0 if x is None else float(variables[name].terms[term](x))
            for hedge in reversed(hedges):
                mu = (
                    mu * mu
                    if hedge == "very"
                    else math.sqrt(mu)
                    if hedge == "somewhat"
                    else 1.0 - mu
                )
            results.append(mu)
        elif not expanded:
            stack.append((node, True))
            stack.extend((child, False) for child in reversed(node[1:]))
        elif kind == "not":
            results.append(1.0 - results.pop())
        else:
            b, a = results.pop(), results.pop()
            results.append(_combine(sem.and_ if kind == "and" else sem.or_, a, b))
    return results[0]
