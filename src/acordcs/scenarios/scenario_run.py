"""Running a scenario (:class:`~acordcs.scenarios.virtual_run.VirtualApplication`) and judging
its expectations: each one holds or is a :class:`Failure` saying what was expected, what was
seen, which rules had fired then (with their degrees) and where the expectation is written.

Times: the run visits every time a step or an expectation names, in order; at each it runs the
clock there (periodic sets fire on the way), gives the step's values (event sets fire on them)
and samples the watched attributes; each firing is sampled too. An expectation ``at`` a time
judges the state then (after that time's step); one ``from``/``to`` judges every sample in the
interval and the state at its start. A rule fired at a time when its set's firing in effect then
gave it a degree above ``min-degree`` (0: any); over an interval, when one of its set's firings in
the interval did. An operation was called at a time when a call happened then (within 1 µs).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from acordcs.errors import AcordError
from acordcs.scenarios.virtual_run import Run, Sample, VirtualApplication

if TYPE_CHECKING:
    from acordcs.runtime.policy import Firing
    from acordcs.scenarios.model_names import ModelNames
    from acordcs.scenarios.scenario_file import Expectation, Scenario
    from acordcs.scenarios.yaml_reading import Located

EPSILON = 1e-6  # seconds: two times this close are one time


@dataclass(frozen=True, slots=True)
class Failure:
    """An expectation that did not hold: ``message`` (expected and seen), ``time`` (when seen),
    ``fired`` (the rules in effect then, with degrees)."""

    expectation: Expectation
    message: str
    time: float
    fired: tuple[tuple[str, float], ...]


@dataclass
class Outcome:
    scenario: Scenario
    run: Run
    failures: list[Failure] = field(default_factory=list)
    faults: list[str] = field(default_factory=list)
    # context documents the provider refused: where the step is, and why
    refused: list[tuple[Located, str]] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def passed(self) -> bool:
        return not self.failures and not self.faults and not self.refused


def watched_names(scenario: Scenario, names: ModelNames) -> list[str]:
    """What a scenario's samples hold: its sets' inputs and outputs, and what it expects of."""
    seen: dict[str, None] = {}
    for s in scenario.policy_sets:
        plan = names.plans[s]
        seen.update(dict.fromkeys((*plan.inputs, *plan.outputs)))
    for e in scenario.expectations:
        if e.kind in ("value", "term"):
            seen[e.name] = None
    return list(seen)


def run_scenario(scenario: Scenario, names: ModelNames) -> Outcome:
    """Run ``scenario`` on the model ``names`` describes, and judge it."""
    import time as wallclock

    started = wallclock.perf_counter()
    try:
        app = VirtualApplication(
            names.app,
            policy_sets=scenario.policy_sets,
            results=scenario.results,
            watched=watched_names(scenario, names),
        )
    except AcordError as exc:  # the runtime refuses to assemble what the model describes
        outcome = Outcome(scenario, Run())
        outcome.faults = [f"the application could not be assembled: {exc}"]
        return outcome
    times = sorted(
        {s.time for s in scenario.steps}
        | {e.start for e in scenario.expectations}
        | {e.end for e in scenario.expectations}
    )
    steps = iter(scenario.steps)
    step = next(steps, None)
    refused: list[tuple[Located, str]] = []
    for t in times:
        app.advance(t)
        while step is not None and step.time <= t:
            app.apply(step.values)
            for publisher, document, where in step.documents:
                try:
                    app.publish(publisher, document)
                except AcordError as exc:
                    refused.append((where, f"the document of {publisher} was refused: {exc}"))
            step = next(steps, None)
        app.sample()
    faults = app.close()
    outcome = Outcome(scenario, app.run)
    outcome.refused = refused
    outcome.faults = [f"{f.kind} {f.where} at t={f.time:g} s: {f.error}" for f in faults]
    judge = _Judge(app.run, names)
    for e in scenario.expectations:
        failure = judge.check(e)
        if failure is not None:
            outcome.failures.append(failure)
    outcome.seconds = wallclock.perf_counter() - started
    return outcome


class _Judge:
    def __init__(self, run: Run, names: ModelNames) -> None:
        self.run = run
        self.names = names
        self.sample_times = [s.time for s in run.samples]
        self.by_set: dict[str, list[Firing]] = {}
        for name, firing in run.firings:
            self.by_set.setdefault(name, []).append(firing)

    # ------------------------------------------------------------------------------ states
    def state_at(self, t: float) -> Sample | None:
        i = bisect.bisect_right(self.sample_times, t + EPSILON)
        return self.run.samples[i - 1] if i else None

    def samples_over(self, a: float, b: float) -> list[Sample]:
        """The state at ``a`` alone when ``b`` is ``a``; else it and every sample up to ``b``."""
        if a == b:
            state = self.state_at(a)
            return [state] if state is not None else []
        lo = bisect.bisect_left(self.sample_times, a - EPSILON)
        hi = bisect.bisect_right(self.sample_times, b + EPSILON)
        first = self.state_at(a)
        return ([first] if first is not None else []) + self.run.samples[lo:hi]

    def firing_at(self, policy_set: str, t: float) -> Firing | None:
        found = None
        for firing in self.by_set.get(policy_set, ()):
            if firing.time > t + EPSILON:
                break
            found = firing
        return found

    def fired_at(self, t: float) -> tuple[tuple[str, float], ...]:
        """The rules with a degree above 0 in each set's firing in effect at ``t``, strongest first."""
        out = []
        for policy_set in self.by_set:
            firing = self.firing_at(policy_set, t)
            if firing is not None:
                out += [
                    (f"{policy_set}.{p}.{label}", degree)
                    for (p, label), degree in firing.rules.items()
                    if degree > 0
                ]
        return tuple(sorted(out, key=lambda r: (-r[1], r[0])))

    # -------------------------------------------------------------------------- judgements
    def check(self, e: Expectation) -> Failure | None:
        return getattr(self, "_" + e.kind.replace("-", "_"))(e)

    def _fail(self, e: Expectation, message: str, t: float) -> Failure:
        return Failure(e, message, t, self.fired_at(t))

    def _when(self, e: Expectation) -> str:
        return f"at t={e.start:g} s" if e.start == e.end else f"from t={e.start:g} to {e.end:g} s"

    def _value(self, e: Expectation) -> Failure | None:
        shown = f"{e.name} = {e.wanted!r}" + (
            f" ± {e.tolerance:g}"
            if isinstance(e.wanted, float | int) and e.tolerance > 1e-9
            else ""
        )
        for sample in self.samples_over(e.start, e.end):
            seen = sample.values.get(e.name)
            if not _close(seen, e.wanted, e.tolerance):
                return self._fail(
                    e,
                    f"expected {shown} {self._when(e)}; seen {_shown(seen)} at t={sample.time:g} s",
                    sample.time,
                )
        return None

    def _term(self, e: Expectation) -> Failure | None:
        variable = self.names.variables[e.name]
        for sample in self.samples_over(e.start, e.end):
            seen = sample.values.get(e.name)
            degrees = variable.memberships(float(seen)) if isinstance(seen, int | float) else {}
            best = max(degrees.values(), default=0.0)
            if best <= 0 or degrees.get(str(e.wanted), 0.0) < best:
                strongest = ", ".join(
                    f"{t} {d:.2f}" for t, d in sorted(degrees.items(), key=lambda x: -x[1]) if d > 0
                )
                return self._fail(
                    e,
                    f"expected {e.name} to be {e.wanted} {self._when(e)}; seen {_shown(seen)} at "
                    f"t={sample.time:g} s ({strongest or 'in no term'})",
                    sample.time,
                )
        return None

    def _degree(self, e: Expectation) -> tuple[float, float]:
        """The rule's strongest degree in the firings ``e`` judges, and when."""
        policy_set, policy, label = e.name.split(".", 2)
        if e.start == e.end:
            firing = self.firing_at(policy_set, e.start)
            firings = [firing] if firing is not None else []
        else:
            firings = [
                f
                for f in self.by_set.get(policy_set, ())
                if e.start - EPSILON <= f.time <= e.end + EPSILON
            ]
        best, when = 0.0, e.start
        for firing in firings:
            degree = firing.rules.get((policy, label), 0.0)
            if degree > best:
                best, when = degree, firing.time
        return best, when

    def _fired(self, e: Expectation) -> Failure | None:
        degree, _ = self._degree(e)
        if degree > e.min_degree:
            return None
        above = f" above {e.min_degree:g}" if e.min_degree else ""
        return self._fail(
            e,
            f"expected rule {e.name} to fire{above} {self._when(e)}; its degree was {degree:.2f}",
            e.end,
        )

    def _not_fired(self, e: Expectation) -> Failure | None:
        degree, when = self._degree(e)
        if degree <= e.min_degree:
            return None
        return self._fail(
            e,
            f"expected rule {e.name} not to fire {self._when(e)}; it fired with degree {degree:.2f} at t={when:g} s",
            when,
        )

    def _calls(self, e: Expectation) -> list:
        return [
            c
            for c in self.run.calls
            if c.operation == e.name
            and e.start - EPSILON <= c.time <= e.end + EPSILON
            and (e.wanted is None or list(c.args) == list(e.wanted))  # type: ignore[arg-type]
        ]

    def _called(self, e: Expectation) -> Failure | None:
        if self._calls(e):
            return None
        args = "" if e.wanted is None else f" with arguments {list(e.wanted)!r}"  # type: ignore[arg-type]
        others = [
            f"{list(c.args)!r} at t={c.time:g} s" for c in self.run.calls if c.operation == e.name
        ][:5]
        seen = f"calls of it: {', '.join(others)}" if others else "it was not called"
        return self._fail(e, f"expected a call of {e.name}{args} {self._when(e)}; {seen}", e.end)

    def _not_called(self, e: Expectation) -> Failure | None:
        calls = self._calls(e)
        if not calls:
            return None
        c = calls[0]
        return self._fail(
            e,
            f"expected no call of {e.name} {self._when(e)}; called with {list(c.args)!r} at "
            f"t={c.time:g} s (by {c.by or 'no policy set'})",
            c.time,
        )


def _close(seen: object, wanted: object, tolerance: float) -> bool:
    if isinstance(wanted, bool) or not isinstance(wanted, int | float):
        return seen == wanted
    if isinstance(seen, bool) or not isinstance(seen, int | float):
        return False
    return abs(float(seen) - float(wanted)) <= tolerance


def _shown(value: object) -> str:
    return f"{value:.6g}" if isinstance(value, float) else repr(value)
