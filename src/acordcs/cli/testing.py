"""``acordcs-gen test``: run a model's policies against its scenario files in virtual time."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import click

from acordcs.diagnostics import Diagnostic, Severity, diagnostic, printable

if TYPE_CHECKING:
    from acordcs.scenarios.rule_coverage import Coverage
    from acordcs.scenarios.scenario_run import Outcome

SUFFIX = ".scenarios.yaml"


def scenario_files(model: str) -> list[str]:
    """The scenario files beside ``model`` (docs/testing.md): ``<stem>.scenarios.yaml`` and every
    ``*.yaml`` of the directory ``<stem>.scenarios/``, where ``<stem>`` is the model's file name
    without its extension."""
    path = Path(model)
    found = []
    single = path.with_name(path.stem + SUFFIX)
    if single.is_file():
        found.append(str(single))
    folder = path.with_name(path.stem + ".scenarios")
    if folder.is_dir():
        found += sorted(str(p) for p in folder.glob("*.yaml") if p.is_file())
    return found


@click.command(short_help="Run a model's policies against scenarios in virtual time.")
@click.argument("model", type=click.Path(dir_okay=False))
@click.argument("scenarios", nargs=-1, type=click.Path(dir_okay=False))
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "json", "sarif"]),
    default="text",
    show_default=True,
    help="text for people (a line per scenario, file:line:col for each failure), json for "
    "scripts, sarif for code-scanning dashboards (failures as results on the scenario files).",
)
@click.option(
    "--junit",
    "junit",
    type=click.Path(dir_okay=False, writable=True),
    help="Also write the results as JUnit XML to FILE (as CI systems show test results).",
)
@click.option(
    "--min-coverage",
    type=click.FloatRange(0, 100),
    default=None,
    help="Fail (exit 1) when the scenarios fire less than N % of the model's rules.",
)
@click.option(
    "--trace",
    "trace",
    type=click.Path(file_okay=False),
    help="Write into DIR, per scenario, a CSV of every input, output and rule degree per step and "
    "a plot of them (SVG and PNG; needs matplotlib: pip install 'acordcs[plots]').",
)
def test(
    model: str,
    scenarios: tuple[str, ...],
    fmt: str,
    junit: str | None,
    min_coverage: float | None,
    trace: str | None,
) -> None:
    """Run the policies of MODEL against SCENARIOS (YAML files; default: MODEL's stem +
    .scenarios.yaml, and the *.yaml of the directory MODEL's stem + .scenarios/, beside it), in
    virtual time, without generating or starting the application: operations the policies call
    are recorded, not run. The format is in docs/testing.md.

    Exit 0 when every scenario passes, 1 when one fails (or the rule coverage is under
    --min-coverage), 2 when the model does not validate or a scenario file cannot be used.

    \b
    Examples:
      acordcs-gen test samples/weblab/weblab.xmi
      acordcs-gen test model.uml checks/hot-day.yaml --junit results.xml
    """
    from acordcs.cli.inputs import read_one
    from acordcs.generator.describe import describe
    from acordcs.scenarios.model_names import ModelNames
    from acordcs.scenarios.rule_coverage import coverage
    from acordcs.scenarios.scenario_file import read_scenarios
    from acordcs.scenarios.scenario_run import run_scenario
    from acordcs.scenarios.yaml_reading import ScenarioFileError, read_scenario_yaml

    if trace is not None:
        from acordcs.scenarios.trace_files import MISSING_PLOTS, plots_available

        if not plots_available():
            raise click.UsageError(MISSING_PLOTS)
    reading = read_one(model)
    errors = [d for d in reading.diagnostics if d.severity >= Severity.ERROR]
    if reading.unreadable or errors or reading.architecture is None:
        _sarif_of_refusal(fmt, errors or reading.diagnostics)
        for d in errors or reading.diagnostics:
            click.echo(d.format_text(), err=True)
        click.echo(
            f"{printable(model)}: the model does not validate ({len(errors)} "
            f"error{'s' if len(errors) != 1 else ''}): no scenario was run; fix the model "
            "(acordcs-gen validate shows every finding)",
            err=True,
        )
        raise click.exceptions.Exit(2)
    files = list(scenarios) or scenario_files(model)
    if not files:
        stem = Path(model).stem
        raise click.UsageError(
            f"no scenario files given, and none beside {printable(model)} ({stem}{SUFFIX}, "
            f"or *.yaml in {stem}.scenarios/); see docs/testing.md for the format"
        )
    names = ModelNames.of(describe(reading.architecture))
    problems: list[Diagnostic] = []
    loaded = []
    for file in files:
        try:
            loaded += read_scenarios(read_scenario_yaml(file), names)
        except ScenarioFileError as exc:
            problems.append(exc.diagnostic)
    if problems:
        _sarif_of_refusal(fmt, problems)
        for d in problems:
            click.echo(d.format_text(), err=True)
        click.echo(
            f"{len(problems)} scenario file{'s' if len(problems) != 1 else ''} could not be "
            "used: no scenario was run",
            err=True,
        )
        raise click.exceptions.Exit(2)
    outcomes = [run_scenario(s, names) for s in loaded]
    covered = coverage(names, outcomes)
    findings = _findings(model, outcomes, covered)
    failed = any(not o.passed for o in outcomes)
    short = min_coverage is not None and covered.percent < min_coverage
    code = 1 if failed or short else 0
    if junit:
        from acordcs.scenarios.junit_report import junit_xml

        try:
            Path(junit).write_bytes(junit_xml(model, outcomes))
        except OSError as exc:
            raise _unwritable(junit, exc) from None
    if trace is not None:
        from acordcs.scenarios.trace_files import write_traces

        try:
            write_traces(trace, outcomes, names)
        except OSError as exc:
            raise _unwritable(trace, exc) from None
    if fmt == "sarif":
        from acordcs.cli.report import sarif_of

        click.echo(json.dumps(sarif_of(findings, exit_code=code), indent=2))
    elif fmt == "json":
        click.echo(json.dumps(_as_json(outcomes, covered, findings), indent=2))
    else:
        click.echo(_as_text(outcomes, covered, findings, min_coverage), nl=False)
    raise click.exceptions.Exit(code)


def _sarif_of_refusal(fmt: str, found: list[Diagnostic]) -> None:
    """With --format sarif, what refused the run as SARIF too (a dashboard shows it), exit 2."""
    if fmt == "sarif":
        from acordcs.cli.report import sarif_of

        click.echo(json.dumps(sarif_of(found, exit_code=2), indent=2))


def _unwritable(path: str, exc: OSError) -> click.FileError:
    error = click.FileError(path, hint=f"cannot write it: {exc.strerror or exc}")
    error.exit_code = 2
    return error


def _findings(model: str, outcomes: list[Outcome], covered: Coverage) -> list[Diagnostic]:
    from acordcs.scenarios.junit_report import failure_text

    found = []
    for o in outcomes:
        for f in o.failures:
            at = f.expectation.at
            found.append(
                diagnostic(
                    "S810",
                    f"scenario {o.scenario.name!r}: {failure_text(f, '; ')}",
                    file=at.file,
                    line=at.line,
                    column=at.column,
                    subject=f"{o.scenario.name}#{o.scenario.expectations.index(f.expectation)}",
                )
            )
        for at, why in o.refused:
            found.append(
                diagnostic(
                    "S811",
                    f"scenario {o.scenario.name!r}: {why}",
                    file=at.file,
                    line=at.line,
                    column=at.column,
                    subject=o.scenario.name,
                )
            )
        for fault in o.faults:
            at = o.scenario.at
            found.append(
                diagnostic(
                    "S811",
                    f"scenario {o.scenario.name!r}: {fault}",
                    file=o.scenario.file,
                    line=at.line if at else 0,
                    column=at.column if at else 0,
                    subject=o.scenario.name,
                )
            )
    unfired: dict[str, list[str]] = {}
    for rule in covered.unfired:
        policy_set, _, rest = rule.partition(".")
        unfired.setdefault(policy_set, []).append(rest)
    for policy_set, rules in unfired.items():
        found.append(
            diagnostic(
                "S812",
                f"{len(rules)} rule{'s' if len(rules) != 1 else ''} of policy set {policy_set} "
                f"fired in no scenario: {', '.join(rules)}",
                file=model,
                element=policy_set,
            )
        )
    unreached: dict[str, list[str]] = {}
    for variable, term in covered.unreached:
        unreached.setdefault(variable, []).append(term)
    for variable, terms in unreached.items():
        found.append(
            diagnostic(
                "S812",
                f"no input reached term{'s' if len(terms) != 1 else ''} {', '.join(terms)} of "
                f"{variable}",
                file=model,
                element=variable,
            )
        )
    return found


def _as_text(
    outcomes: list[Outcome], covered: Coverage, findings: list[Diagnostic], minimum: float | None
) -> str:
    from acordcs.scenarios.junit_report import rules_text

    lines = []
    for o in outcomes:
        s = o.scenario
        verdict = "PASS" if o.passed else "FAIL"
        lines.append(
            printable(
                f"{verdict} {s.file}: {s.name} ({_count(len(s.steps), 'step')}, "
                f"{_count(len(s.expectations), 'expectation')})"
            )
        )
        for f in o.failures:
            at = f.expectation.at
            lines.append(
                "  "
                + diagnostic(
                    "S810", f.message, file=at.file, line=at.line, column=at.column
                ).format_text()
            )
            lines.append(printable(f"      {rules_text(f)}"))
        for at, why in o.refused:
            lines.append(
                "  "
                + diagnostic(
                    "S811", why, file=at.file, line=at.line, column=at.column
                ).format_text()
            )
        lines += [f"  {s.file}: error: S811 {printable(fault)}" for fault in o.faults]
    lines += [d.format_text() for d in findings if d.code == "S812"]
    passed = sum(1 for o in outcomes if o.passed)
    percent = covered.percent
    total = len(covered.rules)
    fired = len(covered.fired)
    under = (
        f" (under --min-coverage {minimum:g} %)"
        if minimum is not None and percent < minimum
        else ""
    )
    lines.append(
        f"{_count(len(outcomes), 'scenario')}: {passed} passed, {len(outcomes) - passed} failed; "
        f"rules fired: {fired} of {total} ({percent:.0f} %){under}"
    )
    return "\n".join(lines) + "\n"


def _as_json(outcomes: list[Outcome], covered: Coverage, findings: list[Diagnostic]) -> dict:
    return {
        "scenarios": [
            {
                "file": o.scenario.file,
                "name": o.scenario.name,
                "passed": o.passed,
                "seconds": o.seconds,
                "failures": [
                    {
                        "location": f.expectation.at.where(),
                        "message": f.message,
                        "time": f.time,
                        "rules": [{"rule": r, "degree": d} for r, d in f.fired],
                    }
                    for f in o.failures
                ],
                "faults": o.faults + [f"{at.where()}: {why}" for at, why in o.refused],
            }
            for o in outcomes
        ],
        "coverage": {
            "percent": covered.percent,
            "unfired": covered.unfired,
            "unreached": [{"variable": v, "term": t} for v, t in covered.unreached],
        },
        "diagnostics": [d.to_dict() for d in findings],
    }


def _count(n: int, what: str) -> str:
    return f"{n} {what}{'s' if n != 1 else ''}"
