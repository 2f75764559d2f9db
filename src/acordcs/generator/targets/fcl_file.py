"""A fuzzy policy set of the descriptor as an FCL function block jFuzzyLogic reads.

The file is the engine the runtime runs for the set, written out: the fuzzy engine built from the
set's plan (:func:`acordcs.engines.fuzzy.engine_for_plan` over
:func:`acordcs.engines.plan.plan_from_descriptor`: the rules as the descriptor resolved them) and
written by the runtime's own FCL writer (:func:`acordcs.engines.fuzzy.fcl_writer.write_fcl`), so
reading the file back with :func:`acordcs.engines.fuzzy.read_fcl` gives an engine with the same
results.

FCL (and jFuzzyLogic) names are plain identifiers and its keywords are reserved, in any case:
``Locomotion.maxSpeed`` becomes ``Locomotion_maxSpeed``, and a name that is an FCL keyword or
already taken gets ``_`` appended (``min`` -> ``min_``) until it is free. The file's header
comment lists every renaming.
"""

from __future__ import annotations

from dataclasses import dataclass

from acordcs.descriptor import PolicySet
from acordcs.engines.fuzzy.fcl_writer import Names
from acordcs.generator.targets.refused_names import require_identifiers

# Our FCL grammar's keywords and jFuzzyLogic's (its lexer reserves them in any case).
FCL_KEYWORDS = frozenset(
    """ABS ACCU ACT AND ASUM BDIF BSUM COA COG COGF COGS COS COSINE DEFAULT DEFUZZIFY DMAX DMIN
    DSIGM EINSTEIN END_DEFUZZIFY END_FUNCTION_BLOCK END_FUZZIFY END_RULEBLOCK END_VAR EXP FUNCTION
    FUNCTION_BLOCK FUZZIFY GAUSS GAUSS2 GBELL HAMACHER IF IS LM LN LOG MAX METHOD MIN MM NC NIPMAX
    NIPMIN NOT NSUM OR PROBOR PROD RANGE REAL RM RULE RULEBLOCK SIGM SIN SINGLETONS SOMEWHAT SUM
    TAN TERM THEN TRAPE TRIAN VAR_INPUT VAR_OUTPUT VERY WITH""".split()
)


class _Free:
    """Allocates FCL names: free of keywords and of the names already given."""

    def __init__(self) -> None:
        self.used: set[str] = set()

    def take(self, wanted: str) -> str:
        name = wanted
        while name.upper() in FCL_KEYWORDS or name.casefold() in self.used:
            name += "_"
        self.used.add(name.casefold())
        return name


class FclNames(Names):
    """The FCL identifier of each name of one engine, and the renamings made (what, model name,
    FCL name). The function block, variables and rule blocks share one namespace; a variable's
    terms and a rule block's labels have their own."""

    def __init__(self) -> None:
        self.renamed: list[tuple[str, str, str]] = []
        self._shared = _Free()
        self._given: dict[tuple[str, str], str] = {}
        self._scoped: dict[str, _Free] = {}

    def _take(self, what: str, key: str, wanted: str, free: _Free) -> str:
        found = self._given.get((what, key))
        if found is None:
            found = self._given[what, key] = free.take(wanted)
            if found != key.rpartition("\0")[2]:
                self.renamed.append((what, key.rpartition("\0")[2], found))
        return found

    def block(self, name: str) -> str:
        return self._take("policy set", name, name, self._shared)

    def variable(self, name: str) -> str:
        return self._take("variable", name, name.replace(".", "_"), self._shared)

    def ruleset(self, name: str) -> str:
        return self._take("policy", name, name, self._shared)

    def term(self, variable: str, term: str) -> str:
        free = self._scoped.setdefault(f"term\0{variable}", _Free())
        return self._take(f"term of {variable}", f"{variable}\0{term}", term, free)

    def label(self, ruleset: str, label: str) -> str:
        free = self._scoped.setdefault(f"label\0{ruleset}", _Free())
        return self._take(f"rule label in {ruleset}", f"{ruleset}\0{label}", label, free)


@dataclass(frozen=True)
class FclFile:
    """The FCL text of one policy set, and the renamings (model name -> FCL name) it made."""

    text: str
    renamed: tuple[tuple[str, str, str], ...]  # (what, model name, FCL name)
    hedged: bool  # some rule uses VERY or SOMEWHAT (our extension)


def _check(ps: PolicySet) -> None:
    names: list[tuple[str, object, str, str]] = [("policy set", ps.name, ps.id, ps.qualified_name)]
    for p in ps.policies:
        names.append(("policy", p.name, p.id, p.qualified_name))
        names += [("rule label", r.label, p.id, p.qualified_name) for r in p.rules]
    for b in ps.bound:
        for part in b.element.split("."):
            names.append(("element", part, b.id, ps.qualified_name))
        names.append(("attribute", b.member, b.id, ps.qualified_name))
    for v in ps.variables:
        names += [("element", part, v.id, v.qualified_name) for part in v.element.split(".")]
        names.append(("attribute", v.attribute, v.id, v.qualified_name))
        names += [("term", t.name, v.id, v.qualified_name) for t in v.terms]
    require_identifiers(names)


def _hedged(condition: tuple) -> bool:
    stack = [condition]
    while stack:
        node = stack.pop()
        if node[0] == "is":
            if any(h != "not" for h in node[2]):
                return True
        elif node[0] == "not":
            stack.append(node[1])
        else:
            stack += [node[1], node[2]]
    return False


def fcl_for(ps: PolicySet) -> FclFile:
    """The FCL function block of a fuzzy policy set. Raises NameRefused (a name that is not an
    identifier) or RuleError (a rule the engine refuses: validate the model first)."""
    from acordcs.engines.fuzzy import engine_for_plan
    from acordcs.engines.fuzzy.fcl_writer import write_fcl
    from acordcs.engines.plan import plan_from_descriptor

    _check(ps)
    engine = engine_for_plan(plan_from_descriptor(ps))
    names = FclNames()
    text = write_fcl(engine, names)
    hedged = any(_hedged(entry.condition) for rs in engine.rulesets() for entry in engine.rules(rs))
    return FclFile(text, tuple(names.renamed), hedged)
