"""The scenario format (docs/testing.md): a YAML file holding several scenarios, each the context
given over virtual time and what the model's policies are expected to do, read into
:class:`Scenario` values with every name checked against the model (:class:`ModelNames`) and
every value's place kept for the diagnostics (S803 a key or shape that is not the format's,
S804 a name the model does not have, with a "did you mean"; S805 a value of the wrong type,
not finite, or outside its variable's range; S806 a limit exceeded).

    scenarios:
      - name: hot afternoon
        policy-sets: [VentControl]          # optional (a container: its sets): every set
        results: {Vent.calibrate: 0}        # optional: what operations return (else None)
        steps:
          - {at: 0, set: {Sensor.temperature: 35}}
          - {at: 5, context: {publisher: Station, document: "<air><temperature>36</temperature></air>"}}
        expect:
          - {at: 0, value: {Vent.opening: 85}, tolerance: 5}
          - {at: 0, term: {Vent.opening: wide}}
          - {from: 0, to: 10, fired: [hotWide], not-fired: [coolShut]}
          - {at: 0, called: {operation: Vent.calibrate, args: [1]}}
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any

from acordcs.diagnostics import suggestion
from acordcs.scenarios.csv_steps import read_csv_cells
from acordcs.scenarios.model_names import ModelNames
from acordcs.scenarios.yaml_reading import Keyed, Located

MAX_SCENARIOS = 1_000
MAX_STEPS = 100_000  # per scenario
MAX_EXPECTATIONS = 10_000  # per scenario
MAX_TIME = 1e9  # seconds of virtual time
MAX_DOCUMENT = 65_536  # characters of one context document
MAX_PERIODIC_FIRINGS = 1_000_000  # of one periodic policy set in a scenario

KINDS = ("value", "term", "fired", "not-fired", "called", "not-called")


@dataclass(frozen=True, slots=True)
class Step:
    """A step: at ``time``, the ``values`` given (Element.attribute -> value, in the file's
    order), then the context ``documents`` published ((publisher, XML text, where the text is),
    for the monitors that subscribe with XPath)."""

    time: float
    values: tuple[tuple[str, object], ...]
    at: Located
    documents: tuple[tuple[str, str, Located], ...] = ()


@dataclass(frozen=True, slots=True)
class Expectation:
    """One expectation: ``kind`` (one of :data:`KINDS`) at ``start`` (``end`` equal) or over
    [``start``, ``end``]; ``name`` the attribute, rule (PolicySet.Policy.label) or operation;
    ``wanted`` the value, term or the call's arguments (None: any); ``at`` where it is written."""

    kind: str
    start: float
    end: float
    name: str
    wanted: object
    tolerance: float
    min_degree: float
    at: Located


@dataclass
class Scenario:
    name: str
    file: str
    policy_sets: tuple[str, ...]
    steps: list[Step]
    expectations: list[Expectation]
    results: dict[str, object] = field(default_factory=dict)
    at: Located | None = None


def read_scenarios(root: Located, names: ModelNames) -> list[Scenario]:
    """The scenarios of a file's tree. Raises ScenarioFileError."""
    top = _mapping(root, "the file", required=("scenarios",), allowed=("scenarios",))
    items = _list(top["scenarios"], "scenarios")
    if not items:
        raise top["scenarios"].fail("S803", "'scenarios' is empty; give at least one scenario")
    if len(items) > MAX_SCENARIOS:
        raise items[MAX_SCENARIOS].fail("S806", f"more than {MAX_SCENARIOS} scenarios in a file")
    out: list[Scenario] = []
    seen: dict[str, Located] = {}
    for item in items:
        scenario = _scenario(item, names)
        if scenario.name in seen:
            raise item.value["name"].fail(
                "S803",
                f"scenario {scenario.name!r} is named twice (first at line {seen[scenario.name].line})",
            )
        seen[scenario.name] = item
        out.append(scenario)
    return out


def _scenario(item: Located, names: ModelNames) -> Scenario:
    fields = _mapping(
        item,
        "a scenario",
        required=("name",),
        allowed=("name", "policy-sets", "results", "steps", "csv", "expect"),
    )
    name = _string(fields["name"], "the scenario's name")
    sets = tuple(names.plans)
    if "policy-sets" in fields:
        chosen: dict[str, None] = {}
        for s in _list(fields["policy-sets"], "policy-sets"):
            if isinstance(s.value, str) and s.value in names.containers:  # a container's sets
                chosen.update(dict.fromkeys(names.containers[s.value]))
            else:
                chosen[_choice(s, {**names.plans, **names.containers}, "policy set")] = None
        sets = tuple(chosen)
        if not sets:
            raise fields["policy-sets"].fail(
                "S803", "'policy-sets' names no policy set; leave it out for all"
            )
    results: dict[str, object] = {}
    if "results" in fields:
        for key, value in _mapping(fields["results"], "results").items():
            op = _choice(fields["results"].value.keys_at[key], names.operations, "operation")
            results[op] = _plain(value)
    steps = [_step(s, names) for s in _list(fields["steps"], "steps")] if "steps" in fields else []
    if "csv" in fields:
        steps = sorted(steps + _csv_steps(fields["csv"], names), key=lambda s: s.time)
    if not steps:
        raise item.fail("S803", "a scenario needs 'steps', or a 'csv' file with at least one row")
    if len(steps) > MAX_STEPS:
        raise steps[MAX_STEPS].at.fail("S806", f"more than {MAX_STEPS} steps in a scenario")
    for before, after in itertools.pairwise(steps):
        if after.time < before.time:
            raise after.at.fail(
                "S805",
                f"step at t={after.time:g} s comes after one at t={before.time:g} s; "
                "give the steps in time order",
            )
    expectations: list[Expectation] = []
    for e in _list(fields["expect"], "expect") if "expect" in fields else []:
        expectations += _expectations(e, names, sets)
        if len(expectations) > MAX_EXPECTATIONS:
            raise e.fail("S806", f"more than {MAX_EXPECTATIONS} expectations in a scenario")
    _check_firings(steps, expectations, names, sets)
    return Scenario(name, item.file, sets, steps, expectations, results, item)


def _step(item: Located, names: ModelNames) -> Step:
    fields = _mapping(item, "a step", required=("at",), allowed=("at", "set", "context"))
    if "set" not in fields and "context" not in fields:
        raise item.fail("S803", "a step needs 'set' (values) or 'context' (documents), or both")
    time = _time(fields["at"])
    values = []
    if "set" in fields:
        for key, value in _mapping(fields["set"], "'set'").items():
            name = _choice(fields["set"].value.keys_at[key], names.attributes, "attribute")
            values.append((name, _typed(value, name, names)))
    documents = []
    if "context" in fields:
        node = fields["context"]
        for doc in _list(node, "'context'") if isinstance(node.value, list) else [node]:
            spec = _mapping(
                doc,
                "a context document",
                required=("publisher", "document"),
                allowed=("publisher", "document"),
            )
            text = spec["document"].value
            if not isinstance(text, str) or len(text) > MAX_DOCUMENT:
                raise spec["document"].fail(
                    "S805", f"a document is XML text of at most {MAX_DOCUMENT} characters"
                )
            documents.append((_string(spec["publisher"], "a publisher"), text, spec["document"]))
    return Step(time, tuple(values), fields["at"], tuple(documents))


def _check_firings(
    steps: list[Step], expectations: list[Expectation], names: ModelNames, sets: tuple[str, ...]
) -> None:
    """A periodic set fires frequency x duration times: bounded, as the steps are."""
    last = max(
        [(s.time, s.at) for s in steps] + [(e.end, e.at) for e in expectations],
        key=lambda x: x[0],
    )
    for name in sets:
        frequency = names.periodic.get(name)
        if frequency and frequency * last[0] > MAX_PERIODIC_FIRINGS:
            raise last[1].fail(
                "S806",
                f"policy set {name} fires at {frequency:g} Hz: {last[0]:g} s of virtual time "
                f"is more than {MAX_PERIODIC_FIRINGS} firings; shorten the scenario",
            )


def _csv_steps(node: Located, names: ModelNames) -> list[Step]:
    """The steps of the CSV file ``node`` names: a header ``time`` then attributes, a row a step."""
    steps = []
    for time, cells in read_csv_cells(node, _string(node, "'csv' (a file name)")):
        values = []
        for header, cell in cells:
            name = _choice(header, names.attributes, "attribute")
            values.append((name, _typed(cell, name, names)))
        steps.append(Step(_time(time), tuple(values), time))
        if len(steps) > MAX_STEPS:
            raise time.fail("S806", f"more than {MAX_STEPS} steps in a scenario")
    return steps


def _expectations(item: Located, names: ModelNames, sets: tuple[str, ...]) -> list[Expectation]:
    fields = _mapping(
        item,
        "an expectation",
        allowed=("at", "from", "to", "tolerance", "min-degree", *KINDS),
    )
    kinds = [k for k in KINDS if k in fields]
    if not kinds:
        raise item.fail("S803", f"an expectation needs one of {', '.join(KINDS)}")
    if "at" in fields:
        if "from" in fields or "to" in fields:
            raise fields["at"].fail("S803", "give 'at' or 'from' and 'to', not both")
        start = end = _time(fields["at"])
    elif "from" in fields and "to" in fields:
        start, end = _time(fields["from"]), _time(fields["to"])
        if end < start:
            raise fields["to"].fail("S805", f"'to' ({end:g} s) is before 'from' ({start:g} s)")
    else:
        raise item.fail("S803", "an expectation needs 'at', or 'from' and 'to' (seconds)")
    tolerance = _number(fields["tolerance"], "tolerance") if "tolerance" in fields else 1e-9
    if tolerance < 0:
        raise fields["tolerance"].fail("S805", "tolerance must be >= 0")
    degree = _number(fields["min-degree"], "min-degree") if "min-degree" in fields else 0.0
    if not 0 <= degree < 1:
        raise fields["min-degree"].fail(
            "S805", "min-degree must be in 0..1 (a rule fired above it)"
        )
    out = []

    def add(kind: str, name: str, wanted: object, at: Located) -> None:
        out.append(Expectation(kind, start, end, name, wanted, tolerance, degree, at))

    for kind in kinds:
        node = fields[kind]
        if kind in ("value", "term"):
            for key, value in _mapping(node, f"'{kind}'").items():
                key_at = node.value.keys_at[key]
                if kind == "value":
                    name = _choice(key_at, names.attributes, "attribute")
                    add(kind, name, _typed(value, name, names, ranged=False), key_at)
                else:
                    name = _choice(key_at, names.variables, "linguistic variable")
                    term = _choice(value, names.variables[name].terms, f"term of {name}")
                    add(kind, name, term, key_at)
        elif kind in ("fired", "not-fired"):
            rules = _rule_names(names, sets)
            for rule in _list(node, f"'{kind}'") if isinstance(node.value, list) else [node]:
                add(kind, _rule(rule, rules), None, rule)
        else:
            calls = [node] if not isinstance(node.value, list) else _list(node, f"'{kind}'")
            for call in calls:
                if isinstance(call.value, Keyed):
                    spec = _mapping(
                        call, "a call", required=("operation",), allowed=("operation", "args")
                    )
                    op = _choice(spec["operation"], names.operations, "operation")
                    args = (
                        tuple(_plain(a) for a in _list(spec["args"], "args"))
                        if "args" in spec
                        else None
                    )
                    add(kind, op, args, spec["operation"])
                else:
                    add(kind, _choice(call, names.operations, "operation"), None, call)
    return out


# ------------------------------------------------------------------------- values and names
def _rule_names(names: ModelNames, sets: tuple[str, ...]) -> dict[str, list[str]]:
    """Each way a rule may be written (label, Policy.label, PolicySet.Policy.label) -> the rules."""
    found: dict[str, list[str]] = {}
    for s, policy, label in names.rules(sets):
        full = f"{s}.{policy}.{label}"
        for written in (label, f"{policy}.{label}", full):
            found.setdefault(written, []).append(full)
    return found


def _rule(node: Located, rules: dict[str, list[str]]) -> str:
    written = _string(node, "a rule")
    found = rules.get(written)
    if not found:
        raise node.fail(
            "S804",
            f"no rule {written!r} in the scenario's policy sets{suggestion(written, sorted(rules))}",
        )
    if len(set(found)) > 1:
        raise node.fail(
            "S804", f"rule {written!r} is ambiguous ({', '.join(sorted(set(found)))}); qualify it"
        )
    return found[0]


def _choice(node: Located, known: Any, what: str) -> str:
    name = _string(node, f"a {what}")
    if name not in known:
        raise node.fail(
            "S804", f"the model has no {what} {name!r}{suggestion(name, sorted(known))}"
        )
    return name


def _typed(node: Located, name: str, names: ModelNames, *, ranged: bool = True) -> object:
    """``node``'s value for attribute ``name``: of its kind, finite, within its variable's range."""
    kind = names.attributes[name]
    value = node.value
    if kind in ("int", "double"):
        number = _number(node, name)
        if kind == "int" and number != int(number):
            raise node.fail("S805", f"{name} is an int attribute; {value!r} is not a whole number")
        variable = names.variables.get(name)
        if ranged and variable is not None and not variable.lo <= number <= variable.hi:
            raise node.fail(
                "S805",
                f"{name} = {number:g} is outside its range {variable.lo:g}..{variable.hi:g}",
            )
        return int(number) if kind == "int" else float(number)
    if kind == "bool":
        if not isinstance(value, bool):
            raise node.fail("S805", f"{name} is a bool attribute; write true or false")
        return value
    if not isinstance(value, str):
        raise node.fail("S805", f"{name} is a string attribute; write it in quotes")
    return value


def _number(node: Located, what: str) -> float:
    value = node.value
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise node.fail("S805", f"{what}: {value!r} is not a number")
    if not math.isfinite(value):
        raise node.fail("S805", f"{what}: {value!r} is not a finite number")
    return float(value)


def _time(node: Located) -> float:
    t = _number(node, "a time (seconds)")
    if not 0 <= t <= MAX_TIME:
        raise node.fail("S805", f"a time must be in 0..{MAX_TIME:g} seconds, not {t:g}")
    return t


def _plain(node: Located) -> object:
    """A result or argument: a scalar or a list of them (nothing else reaches an operation)."""
    if isinstance(node.value, list):
        return [_plain(v) for v in node.value]
    if isinstance(node.value, Keyed):
        raise node.fail("S805", "a result or argument is a number, string, boolean or a list")
    if isinstance(node.value, float) and not math.isfinite(node.value):
        raise node.fail("S805", f"{node.value!r} is not a finite number")
    return node.value


def _string(node: Located, what: str) -> str:
    if isinstance(node.value, bool):
        raise node.fail(
            "S803",
            f"{what} must be a name, not the boolean {str(node.value).lower()}: YAML reads yes, "
            "no, on, off, true and false unquoted as booleans; quote it ('off')",
        )
    if not isinstance(node.value, str) or not node.value:
        raise node.fail("S803", f"{what} must be a name (text), not {node.value!r}")
    return node.value


def _list(node: Located, what: str) -> list[Located]:
    if not isinstance(node.value, list):
        raise node.fail("S803", f"{what} must be a list (- item, or [a, b])")
    return node.value


def _mapping(
    node: Located,
    what: str,
    *,
    required: tuple[str, ...] = (),
    allowed: tuple[str, ...] | None = None,
) -> Keyed:
    if not isinstance(node.value, Keyed):
        raise node.fail("S803", f"{what} must be a mapping (key: value)")
    fields = node.value
    if allowed is not None:
        for key in fields:
            if key not in allowed:
                raise fields.keys_at[key].fail(
                    "S803",
                    f"unknown key {key!r} in {what}{suggestion(key, list(allowed))}; "
                    f"the keys are {', '.join(allowed)}",
                )
    for key in required:
        if key not in fields:
            raise node.fail("S803", f"{what} needs '{key}'")
    return fields
