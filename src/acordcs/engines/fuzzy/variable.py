"""Linguistic variables: a name, a range (universe) and named terms, plus what an output does when
no rule fires for it (DEFAULT, or NC: keep the last value)."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from acordcs.engines.fuzzy.membership import Membership, fmt_number, make_membership
from acordcs.engines.fuzzy.semantics import METHODS
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import RuleSyntaxError, TermDef, parse_terms
from acordcs.rules.tree import MAX_TERMS

TermsSpec = str | Iterable[TermDef] | Mapping[str, Membership] | None


@dataclass(frozen=True)
class LinguisticVariable:
    """A linguistic variable. ``default``/``keep_last`` only matter for outputs:

    - ``default`` set: the output takes it when no rule fired (FCL ``DEFAULT := v``);
    - ``keep_last`` (FCL ``DEFAULT := NC``), or neither set (jFuzzyLogic's behaviour when DEFAULT is
      left out): the output keeps its current value; if it never had one, the low end of its range.

    ``method`` overrides the rule set's defuzzification method for this output (FCL ``METHOD``).
    ``initial`` is the value before any ``set`` or ``fire``.
    """

    name: str
    lo: float
    hi: float
    terms: dict[str, Membership] = field(default_factory=dict)
    default: float | None = None
    keep_last: bool = False
    method: str | None = None
    initial: float | None = None

    def fallback(self, current: float | None) -> float:
        """The value of an output for which no rule fired."""
        if self.default is not None and not self.keep_last:
            return self.default
        return current if current is not None else self.lo

    def describe_range(self) -> str:
        return f"{fmt_number(self.lo)}..{fmt_number(self.hi)}"


def build_variable(
    name: str,
    lo: float,
    hi: float,
    terms: TermsSpec,
    *,
    default: float | None = None,
    keep_last: bool = False,
    method: str | None = None,
    initial: float | None = None,
) -> LinguisticVariable:
    """Validate everything about a variable; errors say which variable and term, and what to do."""
    where = f"variable {name!r}"
    if not isinstance(name, str) or not name.strip():
        raise RuleError(f"a variable needs a non-empty name, got {name!r}")
    try:
        lo, hi = float(lo), float(hi)
    except (TypeError, ValueError):
        raise RuleError(f"{where}: range ends must be numbers, got {lo!r}..{hi!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo >= hi:
        raise RuleError(f"{where}: range {lo!r}..{hi!r} is empty or not finite; give min < max")
    if default is not None:
        if keep_last:
            raise RuleError(f"{where}: give either a DEFAULT value or keep_last (NC), not both")
        default = _finite(default, f"{where}: DEFAULT")
    if initial is not None:
        initial = min(max(_finite(initial, f"{where}: initial value"), lo), hi)
    if method is not None:
        method = str(method).upper()
        if method not in METHODS:
            raise RuleError(f"{where}: unknown METHOD {method!r}; use one of {', '.join(METHODS)}")
    members = _terms(terms, where)
    for term, mf in members.items():
        a, b = mf.extent()
        if (mf.linear or mf.singleton) and (b < lo or a > hi):
            raise RuleError(
                f"{where}: term {term!r} ({mf.fcl()}) lies outside the range "
                f"{fmt_number(lo)}..{fmt_number(hi)}; move it or widen the range"
            )
    return LinguisticVariable(name, lo, hi, members, default, keep_last, method, initial)


def _finite(value: object, what: str) -> float:
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise RuleError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(out):
        raise RuleError(f"{what} must be a finite number, got {value!r}")
    return out


def too_many_terms(where: str, count: int | None = None) -> str:
    """The message for a variable beyond :data:`MAX_TERMS` (``count`` None: a reader that stops
    at the first term too many)."""
    has = f"{count:,} terms" if count is not None else f"more than {MAX_TERMS:,} terms"
    return (
        f"{where} has {has}; the fuzzy engine takes at most {MAX_TERMS:,} per variable "
        "(every firing and the generated rule set grow with them); merge terms or split the variable"
    )


def _terms(terms: TermsSpec, where: str) -> dict[str, Membership]:
    if terms is None:
        return {}
    if isinstance(terms, Mapping):
        if len(terms) > MAX_TERMS:
            raise RuleError(too_many_terms(where, len(terms)))
        out = {}
        for term, mf in terms.items():
            if not isinstance(mf, Membership):
                raise RuleError(
                    f"{where}: term {term!r} must be a Membership, got {type(mf).__name__}"
                )
            out[str(term)] = mf
        return out
    if isinstance(terms, str):
        if not terms.strip():
            return {}
        try:
            defs = parse_terms(terms)
        except RuleSyntaxError as exc:
            raise RuleError(
                f"{where}: terms do not parse: {exc.message} (column {exc.column}); "
                "write them as 'slow := trape 0 0 40 80; fast := trian 60 200 200'",
                column=exc.column,
            ) from None
    else:
        defs = list(terms)
    if len(defs) > MAX_TERMS:
        raise RuleError(too_many_terms(where, len(defs)))
    out = {}
    for d in defs:
        term = d.name.text if hasattr(d.name, "text") else str(d.name)
        if term in out:
            raise RuleError(
                f"{where}: term {term!r} is defined twice; give each term one definition"
            )
        out[term] = make_membership(d.shape, d.parameters, where=f"{where}, term {term!r}")
    return out
