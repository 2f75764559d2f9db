"""``acordcs-gen update``: apply a changed model to the running application, without a restart."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import click

from acordcs.diagnostics import printable

if TYPE_CHECKING:
    from acordcs.descriptor import Application
    from acordcs.descriptor.diff import Change
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
@click.option(
    "-t",
    "--target",
    "target_names",
    multiple=True,
    metavar="NAME",
    help="Target to build (repeat, or separate with commas), as build takes them; default: the "
    "targets the application was built with (its manifest, .acordcs-manifest.json). The python "
    "target is needed: the containers run its package.",
)
@click.option("--dry-run", is_flag=True, help="Print the plan; change nothing (nor the directory).")
@click.option(
    "--strict",
    is_flag=True,
    help="Change nothing (exit 1) when an operation the new model calls has no code in your "
    "classes (the warnings a container prints at start), or your classes have drifted from the "
    "model (G704).",
)
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
def update(
    model: str,
    output: str,
    target_names: tuple[str, ...],
    dry_run: bool,
    strict: bool,
    reset: bool,
    timeout: float,
) -> int:
    """Build MODEL into --output as build does (the targets it was built with), then change the
    running application to match: the plan (one line per change: + added, - removed, ~ changed)
    is the difference between the descriptor the running containers run and the new one, with
    the code of each component and monitor whose file changed since its container loaded it
    (~ code of component C), and each container applies its part through its management
    interface, atomically (a part that fails is rolled back). An operation the new model calls
    that has no code in your classes is said as a container says it at start (--strict: nothing
    is changed).

    The containers are found as the application's scripts find them (bin/env.sh, with the same
    environment: ACORDCS_RUN_DIR, ACORDCS_TOKEN, ACORDCS_<C>_HOST, ACORDCS_<C>_PORT) and called
    with the application's token. What applies live and what does not: docs/update.md.

    Exit 0 when applied (or nothing to do), 1 when a change cannot be applied live or --strict
    refuses (nothing is changed then: neither the directory nor the application) or a container
    rolled its part back, 2 on usage errors, a model that cannot be read, or no container
    reachable.

    \b
    Examples:
      acordcs-gen update samples/weblab/weblab.xmi -o samples/weblab/app --dry-run
      ACORDCS_RUN_DIR=/tmp/run acordcs-gen update model.xmi -o app
    """
    from acordcs.cli.running import reach
    from acordcs.runtime.live.app_settings import NotFound, settings

    app = Path(output)
    out = printable(click.format_filename(output))
    if not app.is_dir():
        _fail(f"{out} is not a directory: give -o the application's directory", 2)
    try:
        found = settings(app)
    except NotFound as err:
        _fail(_text(err), 2)
    targets = _targets(app, out, target_names)
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
    result, new_data = _build(model, app, found.package, targets)
    from acordcs.descriptor import from_xml

    new = from_xml(new_data, file="the new descriptor")
    missing = _missing(running, new, app, found.package)
    plans = _plans(running, new)
    code = _code(running, new, app)
    show_plans(running, plans, code)
    fixed = [c for plan in plans.values() for c in plan.changes if not c.live]
    if fixed:
        for line in dict.fromkeys(f"{c.line}: cannot apply live: {c.why}" for c in fixed):
            click.echo(f"acordcs-gen update: {printable(line)}", err=True)
        _fail("nothing changed (neither the application's directory nor its containers)", 1)
    if strict and (missing or result.drift):
        why = []
        if missing:
            why.append(
                f"{missing} operation{'s' if missing != 1 else ''} that the model calls "
                f"{'have' if missing != 1 else 'has'} no code (listed above)"
            )
        if result.drift:
            why.append("your classes have drifted from the model (G704, above)")
        _fail(
            f"--strict: {'; '.join(why)}: nothing changed (neither the application's directory "
            "nor its containers)",
            1,
        )
    if dry_run:
        if result.plan is not None:
            from acordcs.cli.build import report_notes

            report_notes(result.plan, out, False, {d.path for d in result.drift})
        click.echo("dry run: nothing changed")
        raise click.exceptions.Exit(0)
    _write(result, app)
    home = (f"{app.resolve()}{os.sep}", f"{out}{os.sep}")
    raise click.exceptions.Exit(_apply(running, plans, code, new_data, found, reset, timeout, home))


# -------------------------------------------------------------------------------------- steps
def _targets(app: Path, out: str, given: tuple[str, ...]) -> list[str]:
    """The targets to build: ``given`` (``-t``, read as ``build`` reads them), else those the
    manifest says the application was built with. The python target must be among them."""
    from acordcs.cli.build import report_failure
    from acordcs.generator import BuildError
    from acordcs.generator.manifest import ManifestError, read_manifest
    from acordcs.generator.paths import MANIFEST
    from acordcs.generator.pipeline import STYLESHEET_SUFFIXES, select

    names = list(given)
    if not names:
        where = f"{out}/{MANIFEST}"
        try:
            manifest = read_manifest(app)
        except ManifestError as err:
            _fail(
                f"{where} cannot be used ({printable(str(err))}): the targets the application "
                "was built with are unknown; give them with -t (as to build)",
                2,
            )
        if manifest is None or not manifest.targets:
            _fail(
                f"{where} is missing or lists no target: the targets the application was built "
                "with are unknown; give them with -t (as to build)",
                2,
            )
        names = sorted(manifest.targets)
        own = [n for n in names if n.lower().endswith(STYLESHEET_SUFFIXES)]
        if own:
            _fail(
                f"the application was built with your stylesheet{'s' if len(own) > 1 else ''} "
                f"{printable(', '.join(own))} ({where}), whose path the manifest does not keep: "
                f"give every target with -t, a stylesheet by its path (-t "
                f"{printable(','.join(n for n in names if n not in own) or 'python')},"
                "path/to/your.xsl)",
                2,
            )
    try:
        chosen = select(names)
    except BuildError as err:
        if not given:
            err.hint = (
                f"the application was built with {', '.join(names)} ({out}/{MANIFEST}); give "
                f"the targets to build with -t ({err.hint})"
            )
        report_failure(err, "update")
        raise click.exceptions.Exit(err.exit_code) from None
    if "python" not in {t.name for t in chosen}:
        _fail(
            f"targets {printable(', '.join(t.name for t in chosen))}: update builds the python "
            "target too (the containers run its package, and read its descriptor.xml): add "
            "python to -t",
            2,
        )
    return names


def _build(model: str, app: Path, package: str, targets: list[str]) -> tuple[BuildResult, bytes]:
    """Build MODEL as ``build`` does, without writing: the build, and the new descriptor."""
    from acordcs.cli.build import report_failure, warn_plugins
    from acordcs.generator import BuildError
    from acordcs.generator import build as run_build

    try:
        result = run_build(model, app, targets, write=False)
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
    from acordcs.generator.paths import Unreadable, read_bounded

    try:
        return result, read_bounded(path)  # a FIFO or a huge file there is refused, not waited on
    except Unreadable as err:
        _fail(f"{printable(str(path))}: cannot read the new descriptor: it is {err.what}", 2)
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


def _plans(running: list, new: Application) -> dict[str, Any]:
    """Each running container's plan: from the descriptor it runs to the new one."""
    from acordcs.descriptor import DescriptorError, from_xml
    from acordcs.descriptor.diff import diff

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


def _code(running: list, new: Application, app: Path) -> dict[str, tuple[Change, ...]]:
    """Per running container, the changes of the code of the components and monitors it hosts
    in the new descriptor: those whose file (the user's, in ``app``) is not what the container
    loaded (the digests its ``status`` gives; a container that gives none is taken as running
    the files as they are)."""
    from acordcs.descriptor.diff import code_change
    from acordcs.generator.manifest import sha256
    from acordcs.generator.paths import path_problem
    from acordcs.runtime.live.code_check import hosted_here

    out: dict[str, tuple[Change, ...]] = {}
    for r in running:
        loaded = r.status.get("code")
        found: list[Change] = []
        here = hosted_here(new, r.name, "component") + hosted_here(new, r.name, "monitor")
        for name in here if isinstance(loaded, dict) else ():
            record = loaded.get(name)
            if not isinstance(record, dict) or record.get("kind") not in ("component", "monitor"):
                continue
            file = str(record.get("file", ""))
            if path_problem(file):
                continue  # not a file of the directory: not ours to read
            try:
                now = sha256((app / file).read_bytes())
            except OSError:
                now = ""  # gone: reading its class afresh says why it fails
            if now != record.get("sha256"):
                found.append(code_change(str(record["kind"]), name, r.name))
        out[r.name] = tuple(found)
    return out


def _missing(running: list, new: Application, app: Path, package: str) -> int:
    """Say, as a container does at start, each operation of the new model that something calls
    in a running container and that has no code in the user's classes; how many."""
    from acordcs.runtime.live.code_check import operations_without_code_in_files

    names = {r.name for r in running}
    count = 0
    for container in new.containers:
        if container.name not in names:
            continue  # not running: its start says it
        for item in operations_without_code_in_files(new, container.name, app, package):
            click.echo(printable(item.message()))
            count += 1
    return count


def show_plans(running: list, plans: dict[str, Any], code: dict[str, tuple[Change, ...]]) -> None:
    """What the update will do, one plan for all containers on one descriptor, else one each."""
    digests = {r.status["digest"] for r in running}
    names = ", ".join(f"{r.name} ({r.host}:{r.port})" for r in running)
    if len(digests) == 1:
        click.echo(f"running: {printable(names)}, descriptor {next(iter(digests))[:12]}")
        every = tuple(c for r in running for c in code[r.name])
        groups = [(None, plans[running[0].name].changes + every)]
    else:
        click.echo(
            f"running: {printable(names)}, on different descriptors (an earlier update reached "
            "only some of them, or they were started from different builds): a plan for each"
        )
        groups = [(r.name, plans[r.name].changes + code[r.name]) for r in running]
    for name, changes in groups:
        live = sum(1 for c in changes if not c.live)
        head = f"plan{f' of {name}' if name else ''}: {len(changes)} change" + (
            "s" if len(changes) != 1 else ""
        )
        if live:
            head += f", {live} cannot apply live"
        click.echo(head + ("" if changes else " (the running application is the model's)"))
        for c in changes:
            click.echo(printable(c.line) + ("" if c.live else "   [cannot apply live]"))


def _apply(
    running: list,
    plans: dict,
    coded: dict[str, tuple[Change, ...]],
    new_data: bytes,
    found,
    reset: bool,
    timeout: float,
    home: tuple[str, str],
) -> int:
    from acordcs.cli.running import apply, container_uri
    from acordcs.descriptor import from_xml
    from acordcs.runtime.live.apply_update import container_order
    from acordcs.runtime.live.management import digest

    new = from_xml(new_data, file="the new descriptor")
    text = new_data.decode("utf-8")
    target = digest(new_data)
    by_name = {r.name: r for r in running}
    every = [c for plan in plans.values() for c in plan.changes]
    every += [c for changes in coded.values() for c in changes]
    objects = {c.name: c.endpoint.object_name for c in new.containers if c.endpoint is not None}
    uris = {n: container_uri(n, h, p, objects.get(n)) for n, (h, p) in found.containers.items()}
    code = 0
    for name in container_order(new, list(by_name), every):
        r = by_name[name]
        reload = [c.element for c in coded.get(name, ())]
        if r.status["digest"] == target and not reload:
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
            r,
            text,
            r.status["digest"],
            others,
            reset,
            reload,
            token=found.token,
            timeout=timeout * 6,
        )
        code = max(code, _report(name, reply, home))
    return code


def _report(name: str, reply: dict[str, Any], home: tuple[str, str] = ("", "")) -> int:
    """Say what container ``name`` replied; ``home``: the application's directory as the
    containers name it (absolute) and as the user gave it, the first written as the second."""
    if home[0]:
        reply = {
            k: (v.replace(home[0], home[1]) if isinstance(v, str) else v) for k, v in reply.items()
        }
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
