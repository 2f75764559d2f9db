"""Named inference semantics: how AND/OR combine, how a rule activates its conclusion, how activated
sets accumulate, and how an output is defuzzified.

- ``mamdani`` (default): AND min, OR max, activation min, accumulation max, exact centroid;
- ``sazonov``: the paper's engine (E. Sazonov's Fuzzy Engine for Java): AND min, OR max, activation
  product, accumulation sum, centroid over 100 evenly spaced samples of the output's range;
- ``fcl``: jFuzzyLogic's defaults for a RULEBLOCK that states nothing: AND min, activation min,
  accumulation SUM (not max), exact centroid.

Any FCL combination is a :class:`Semantics` too: ``Semantics(and_="PROD", act="PROD", accu="PROBOR")``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from acordcs.engines.rule_engine import RuleError

# AND and the OR that goes with it (its De Morgan dual), as jFuzzyLogic pairs them
# (net.sourceforge.jFuzzyLogic.rule.RuleBlock.fclTree).
AND_OPS = {
    "MIN": "MAX",
    "PROD": "ASUM",
    "BDIF": "BSUM",
    "DMIN": "DMAX",
    "NIPMIN": "NIPMAX",
    "HAMACHER": "EINSTEIN",
}
OR_OPS = tuple(AND_OPS.values())
ACT_OPS = ("MIN", "PROD")
ACCU_OPS = ("MAX", "BSUM", "NSUM", "PROBOR", "SUM")
METHODS = ("COG", "COGS", "COA", "LM", "RM", "MM")
SUMS = ("SUM", "NSUM")  # NSUM only rescales the set: every method gives the same crisp value


@dataclass(frozen=True, slots=True)
class Semantics:
    """Operators of a rule set. ``samples``: None for the exact centroid, or the number of evenly
    spaced samples over the range for a discrete one (sum of y*mu over sum of mu, as the paper's
    engine does). ``name`` is informative and not part of equality."""

    and_: str = "MIN"
    or_: str = "MAX"
    act: str = "MIN"
    accu: str = "MAX"
    method: str = "COG"
    samples: int | None = None
    name: str = field(default="custom", compare=False)

    def __post_init__(self) -> None:
        for what, value, allowed in (
            ("AND", self.and_, tuple(AND_OPS)),
            ("OR", self.or_, OR_OPS),
            ("ACT", self.act, ACT_OPS),
            ("ACCU", self.accu, ACCU_OPS),
            ("METHOD", self.method, METHODS),
        ):
            if value not in allowed:
                raise RuleError(
                    f"unknown {what} operator {value!r}; use one of {', '.join(allowed)}"
                )
        if self.samples is not None and (not isinstance(self.samples, int) or self.samples < 2):
            raise RuleError(
                f"samples must be an integer >= 2 or None (exact), got {self.samples!r}"
            )

    def with_(self, **changes: object) -> Semantics:
        """A copy with some operators changed, named after the preset it matches (or ``custom``)."""
        changed = replace(self, **changes)  # type: ignore[arg-type]
        return replace(changed, name=preset_name(changed))


MAMDANI = Semantics("MIN", "MAX", "MIN", "MAX", "COG", None, "mamdani")
SAZONOV = Semantics("MIN", "MAX", "PROD", "SUM", "COG", 100, "sazonov")
FCL_DEFAULTS = Semantics("MIN", "MAX", "MIN", "SUM", "COG", None, "fcl")
PRESETS = {"mamdani": MAMDANI, "sazonov": SAZONOV, "fcl": FCL_DEFAULTS}


def preset_name(semantics: Semantics) -> str:
    for name, preset in PRESETS.items():
        if preset == semantics:
            return name
    return "custom"


def resolve(semantics: str | Semantics) -> Semantics:
    """A Semantics from a preset name (case-insensitive) or a Semantics."""
    if isinstance(semantics, Semantics):
        return semantics
    found = PRESETS.get(str(semantics).lower())
    if found is None:
        raise RuleError(
            f"unknown fuzzy semantics {semantics!r}; use one of {', '.join(PRESETS)} "
            "or a Semantics(...) with FCL operators"
        )
    return found


def connect(op: str, a: float, b: float) -> float:
    """The degree of ``a AND b`` or ``a OR b`` under FCL operator ``op``: the definitions of
    jFuzzyLogic's RuleConnectionMethod* classes (the rule compiler and the batch call write the
    same formulas as code; tests/engines/test_fuzzy_connectives.py holds all three to them)."""
    if op == "MIN":
        return a if a < b else b
    if op == "MAX":
        return a if a > b else b
    if op == "PROD":
        return a * b
    if op == "ASUM":  # probabilistic sum
        return a + b - a * b
    if op == "BDIF":  # bounded difference (Lukasiewicz)
        return max(0.0, a + b - 1.0)
    if op == "BSUM":  # bounded sum
        return min(1.0, a + b)
    if op == "DMIN":  # drastic product
        return b if a == 1.0 else a if b == 1.0 else 0.0
    if op == "DMAX":  # drastic sum
        return b if a == 0.0 else a if b == 0.0 else 1.0
    if op == "NIPMIN":  # nilpotent minimum
        return min(a, b) if a + b > 1.0 else 0.0
    if op == "NIPMAX":  # nilpotent maximum
        return max(a, b) if a + b < 1.0 else 1.0
    if op == "HAMACHER":  # Hamacher product
        return 0.0 if a == 0.0 and b == 0.0 else a * b / (a + b - a * b)
    if op == "EINSTEIN":  # Einstein sum
        return (a + b) / (1.0 + a * b)
    raise RuleError(f"unknown AND/OR operator {op!r}; use one of {', '.join([*AND_OPS, *OR_OPS])}")


def collapses(sem: Semantics, singletons: bool) -> bool:
    """Whether the rules concluding the same term can be folded into one level per term first."""
    return singletons or sem.accu == "MAX" or (sem.act == "PROD" and sem.accu in SUMS)
