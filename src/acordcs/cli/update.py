"""``acordcs-gen update``: apply a changed model to the running application, without a restart."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import click

from acordcs.diagnostics import printable

if TYPE_CHECKING:
    from acordcs.generator import BuildResult


@click.command()
@click.argument("model", type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(file_okay=False),
    help="The application's directory: built by acordcs-gen build, started by its bin/ scripts.",
)
@click.option("--dry-run", is_flag=True, help="Print the plan; change nothing (nor the directory).")
@click.option(
    "--reset",
    is_flag=True,
    help="Set a property's new default also where it was changed at run time.",
)
@click.option(
    "--timeout",
    type=click.FloatRange(min=0.1),
    default=5.0,
    show_default=True,
    help="Seconds to wait for a container's answer (an update's apply: six times as long).",
)
def update(model: str, output: str, dry_run: bool, reset: bool, timeout: float) -> int:
    """Build MODEL into --output as build does, then change the running application to match:
    the plan (one line per change: + added, - removed, ~ changed) is the difference between
    the descriptor the running containers run and the new one, and each container applies its
    part through its management interface, atomically (a part that fails is rolled back).

    The containers are found as the application's scripts find them (bin/env.sh, with the same
    environment: ACORDCS_RUN_DIR, ACORDCS_TOKEN, ACORDCS_<C>_HOST, ACORDCS_<C>_PORT) and called
    with the application's token. What applies live and what does not: docs/update.md.

    Exit 0 when applied (or nothing to do), 1 when a change cannot be applied live (nothing is
    changed then: neither the directory nor the application) or a container rolled its part back,
    2 on usage errors, a model that cannot be read, or no container reachable.

    \b
    Examples:
      acordcs-gen update samples/weblab/weblab.xmi -o samples/weblab/app --dry-run
      ACORDCS_RUN_DIR=/tmp/run acordcs-gen update model.xmi -o app
    """
    from acordcs.cli.running import NotFound, reach, settings

    app = Path(output)
    out = printable(click.format_filename(output))
    if not app.is_dir():
        _fail(f"{out} is not a directory: give -o the application's directory", 2)
    try:
        found = settings(app)
    except NotFound as err:
        _fail(_text(err), 2)
    reached = reach(found, timeout=timeout)
    running = [r for r in reached if r.status is not None]
    for r in reached:
        if r.status is None:
            click.echo(f"{r.name}: {printable(r.problem)}", err=True)
    if not running:
        _fail(
            f"no container of {out} answers where its scripts start them (run directory "
            f"{printable(found.run_dir)}): start it (bin/start-all) with the same environment",
            2,
        )
    result, new_data = _build(model, app, found.package)
    plans = _plans(running, new_data)
    _show(running, plans)
    fixed = [c for plan in plans.values() for c in plan.changes if not c.live]
    if fixed:
        for line in dict.fromkeys(f"{c.line}: cannot apply live: {c.why}" for c in fixed):
            click.echo(f"acordcs-gen update: {printable(line)}", err=True)
        _fail("nothing changed (neither the application's directory nor its containers)", 1)
    if dry_run:
        if result.plan is not None:
            from acordcs.cli.build import report_notes

            report_notes(result.plan, out, False, {d.path for d in result.drift})
        click.echo("dry run: nothing changed")
        raise click.exceptions.Exit(0)
    _write(result, app)
    raise click.exceptions.Exit(_apply(running, plans, new_data, found, reset, timeout))


# -------------------------------------------------------------------------------------- steps
def _build(model: str, app: Path, package: str) -> tuple[BuildResult, bytes]:
    """Build MODEL as ``build`` does, without writing: the build, and the new descriptor."""
    from acordcs.cli.build import report_failure, warn_plugins
    from acordcs.generator import BuildError
    from acordcs.generator import build as run_build

    try:
        result = run_build(model, app, write=False)
    except BuildError as err:
        warn_plugins()
        for note in err.notes:
            click.echo(f"acordcs-gen: {note}", err=True)
        report_failure(err, "update")
        raise click.exceptions.Exit(err.exit_code) from None
    warn_plugins()
    for note in result.notes + result.messages:
        click.echo(f"acordcs-gen: {note}", err=True)
    for warning in result.warnings:
        click.echo(warning.format_text())
    for change in result.plan.changes if result.plan is not None else ():
        parts = change.path.split("/")  # the package's descriptor.xml, which containers read
        if len(parts) == 2 and parts[1] == "descriptor.xml" and change.new is not None:
            return result, change.new
    path = app / package / "descriptor.xml"
    try:
        return result, path.read_bytes()
    except OSError as err:
        _fail(f"{printable(str(path))}: cannot read the new descriptor: {err.strerror}", 2)


def _write(result: BuildResult, app: Path) -> None:
    """Write what :func:`_build` made, as ``build`` does last."""
    from acordcs.cli.build import report_failure, report_notes
    from acordcs.generator import BuildError
    from acordcs.generator.pipeline import write_out

    try:
        write_out(result)
    except BuildError as err:
        report_failure(err, "update")
        raise click.exceptions.Exit(err.exit_code) from None
    plan = result.plan
    out = printable(click.format_filename(str(app)))
    if plan is not None:
        report_notes(plan, out, True, {d.path for d in result.drift})
    if plan is not None and result.written:
        click.echo(
            f"{out}: built: {len(plan.writes)} written, {len(plan.deletes)} deleted, "
            f"{len(plan.unchanged)} unchanged"
        )


def _plans(running: list, new_data: bytes) -> dict[str, Any]:
    """Each running container's plan: from the descriptor it runs to the new one."""
    from acordcs.descriptor import DescriptorError, from_xml
    from acordcs.descriptor.diff import diff

    new = from_xml(new_data, file="the new descriptor")
    olds: dict[str, Any] = {}
    plans = {}
    for r in running:
        digest = r.status["digest"]
        if digest not in olds:
            try:
                olds[digest] = from_xml(r.descriptor.encode("utf-8"), file=f"container {r.name}")
            except DescriptorError as err:
                _fail(f"container {r.name} sent a descriptor that does not read: {err}", 2)
        plans[r.name] = diff(olds[digest], new)
    return plans


def _show(running: list, plans: dict[str, Any]) -> None:
    digests = {r.status["digest"] for r in running}
    names = ", ".join(f"{r.name} ({r.host}:{r.port})" for r in running)
    if len(digests) == 1:
        click.echo(f"running: {printable(names)}, descriptor {next(iter(digests))[:12]}")
        groups = [(None, plans[running[0].name])]
    else:
        click.echo(
            f"running: {printable(names)}, on different descriptors (an earlier update reached "
            "only some of them, or they were started from different builds): a plan for each"
        )
        groups = [(r.name, plans[r.name]) for r in running]
    for name, plan in groups:
        changes = plan.changes
        live = sum(1 for c in changes if not c.live)
        head = f"plan{f' of {name}' if name else ''}: {len(changes)} change" + (
            "s" if len(changes) != 1 else ""
        )
        if live:
            head += f", {live} cannot apply live"
        click.echo(head + ("" if changes else " (the running application is the model's)"))
        for c in changes:
            click.echo(printable(c.line) + ("" if c.live else "   [cannot apply live]"))


def _apply(running: list, plans: dict, new_data: bytes, found, reset: bool, timeout: float) -> int:
    from acordcs.cli.running import apply, container_uri
    from acordcs.descriptor import from_xml
    from acordcs.runtime.live.apply_update import container_order
    from acordcs.runtime.live.management import digest

    new = from_xml(new_data, file="the new descriptor")
    text = new_data.decode("utf-8")
    target = digest(new_data)
    by_name = {r.name: r for r in running}
    every = [c for plan in plans.values() for c in plan.changes]
    objects = {c.name: c.endpoint.object_name for c in new.containers if c.endpoint is not None}
    uris = {n: container_uri(n, h, p, objects.get(n)) for n, (h, p) in found.containers.items()}
    code = 0
    for name in container_order(new, list(by_name), every):
        r = by_name[name]
        if r.status["digest"] == target:
            click.echo(f"{name}: runs descriptor {target[:12]} already: nothing to do")
            continue
        if code:
            click.echo(
                f"{name}: not updated (a container before it failed); runs "
                f"descriptor {r.status['digest'][:12]}"
            )
            continue
        others = {n: u for n, u in uris.items() if n != name}
        reply = apply(
            r, text, r.status["digest"], others, reset, token=found.token, timeout=timeout * 6
        )
        code = max(code, _report(name, reply))
    return code


def _report(name: str, reply: dict[str, Any]) -> int:
    status = reply.get("status")
    after = str(reply.get("digest") or "")[:12]
    if status in ("applied", "unchanged"):
        applied = reply.get("applied") or []
        done = (
            f"applied {len(applied)} change{'s' if len(applied) != 1 else ''} in "
            f"{1000 * float(reply.get('seconds') or 0):.1f} ms"
            if applied
            else "nothing to change"
        )
        click.echo(f"{name}: {done}; runs descriptor {after}")
        for line in reply.get("kept") or []:
            click.echo(f"{name}: {printable(line)}")
        return 0
    error = printable(str(reply.get("error") or "no reason given"))
    if status == "rolled back":
        click.echo(f"{name}: failed: {error}", err=True)
        for line in reply.get("rolled_back") or []:
            click.echo(f"{name}: rolled back: {printable(line)}", err=True)
        for line in reply.get("unrolled") or []:
            click.echo(f"{name}: could not roll back: {printable(line)}", err=True)
        click.echo(f"{name}: runs descriptor {after} as before the update", err=True)
    else:
        click.echo(f"{name}: not updated: {error}", err=True)
    return 1


def _text(err) -> str:
    text = err.message + (f" ({err.hint})" if err.hint else "")
    return printable(text)


def _fail(message: str, code: int) -> NoReturn:
    click.echo(f"acordcs-gen update: {message}", err=True)
    raise click.exceptions.Exit(code)


__all__ = ["update"]
