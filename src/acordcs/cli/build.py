"""``acordcs-gen build``: generate the application's files from a model, writing only what changed."""

from __future__ import annotations

import os
import sys
from collections.abc import Collection

import click

from acordcs.diagnostics import printable


@click.command()
@click.argument("model", type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(file_okay=False),
    help="Directory of the generated files (created if missing).",
)
@click.option(
    "-t",
    "--target",
    "target_names",
    multiple=True,
    metavar="NAME",
    help="Target to build (repeat, or separate with commas); default all. "
    "Built in: config, java, python, rules, shell; acordcs-gen build --list shows every installed one. "
    "A path ending in .xsl or .xslt is your own XSLT 3.0 stylesheet, run over the descriptor as "
    "a built-in target is (the target takes the file's name).",
)
@click.option(
    "--check", is_flag=True, help="Write nothing; exit 1 if the output is not up to date."
)
@click.option(
    "--strict",
    is_flag=True,
    help="Exit 1 also when your classes have drifted from the model (G704: a method of an "
    "operation or port the model renamed or removed) or do not compile (G705: a container "
    "hosting one refuses to start), whatever else happens.",
)
@click.option(
    "--trust-stylesheet",
    "trust_stylesheet",
    is_flag=True,
    help="Run the stylesheets given with -t (and other packages' stylesheet targets) with your "
    "rights: without it each runs confined, reading only the descriptor and the files under its "
    "own directory, with no network and no environment variables.",
)
@click.option(
    "--dry-run", is_flag=True, help="Write nothing; list what would be written or deleted."
)
@click.option(
    "--diff", is_flag=True, help="Write nothing; show a unified diff of what would change."
)
@click.option(
    "--force",
    is_flag=True,
    help="Read the model and run the targets even when the manifest says nothing changed.",
)
@click.option(
    "-q",
    "--quiet",
    is_flag=True,
    help="Do not list the files written or deleted; warnings, notes and the summary line stay.",
)
@click.option(
    "--list",
    is_flag=True,
    is_eager=True,
    expose_value=False,
    callback=lambda ctx, _param, value: _list(ctx) if value else None,
    help="List the targets (built in and installed) and exit.",
)
def build(
    model: str,
    output: str,
    target_names: tuple[str, ...],
    check: bool,
    strict: bool,
    trust_stylesheet: bool,
    dry_run: bool,
    diff: bool,
    force: bool,
    quiet: bool,
) -> int:
    """Generate the files of MODEL's application into --output: the deployment descriptor and its
    schema (config), a Python package with the components' classes and a module per container
    (python), Java sources with a base class and a user subclass per component (java), one FCL or
    CLIPS file per policy set (rules), sh scripts starting, stopping and checking each container
    (shell).

    The model is validated first (an error stops the build, nothing written); only files whose
    bytes changed are written; generated files the model no longer makes are deleted (the manifest
    .acordcs-manifest.json says which files are generated: no other file is ever touched); files
    written once for the user to edit (python's components/*.py and monitors/*.py, java's user subclasses) are never overwritten or deleted,
    nor are the lines between BEGIN USER and END USER markers (shell's bin/env.sh).

    Before writing, your classes (python's components/*.py) are compared with the model: a method
    of an operation or port the model renamed (the new name given) or removed is a warning (G704).

    Your own stylesheets (-t mine.xsl) run confined: they read only the descriptor and the files
    under their own directory, reach no network and see no environment variable;
    --trust-stylesheet runs them with your rights.

    Exit 0 when built (or up to date), 1 when the model has errors, a target fails, --check finds
    the output out of date, or --strict finds your classes drifted from the model or not
    compiling, 2 on usage
    errors and unreadable or unwritable files.

    \b
    Examples:
      acordcs-gen build samples/weblab/weblab.xmi -o build/weblab
      acordcs-gen build model.xmi -o gen --target rules --check
      acordcs-gen build model.xmi -o gen --check --strict
    """
    from acordcs.generator import BuildError
    from acordcs.generator import build as run_build

    write = not (check or dry_run or diff)
    progress = _Bar(len(_count(target_names)) + 4) if sys.stderr.isatty() else None
    try:
        result = run_build(
            model,
            output,
            target_names or None,
            write=write,
            force=force,
            check=check,
            drift=strict,
            progress=progress.step if progress else None,
            trust_stylesheets=trust_stylesheet,
        )
    except BuildError as err:
        if progress:
            progress.close()
        warn_plugins()
        for note in err.notes:  # a stylesheet's xsl:message among them: escaped
            click.echo(f"acordcs-gen: {printable(note)}", err=True)
        report_failure(err)
        raise click.exceptions.Exit(err.exit_code) from None
    if progress:
        progress.close()
    warn_plugins()
    for note in result.notes + result.messages:  # a stylesheet's text: no line of its own
        click.echo(f"acordcs-gen: {printable(note)}", err=True)
    for warning in result.warnings:
        click.echo(warning.format_text())
    # paths as given: a newline in one must not start a forged line of output
    out = printable(click.format_filename(output))
    drifted = 1 if strict and result.drift else 0
    if result.up_to_date:
        click.echo(
            f"{out}: up to date ({', '.join(result.targets)}; model unchanged, nothing written)"
        )
        raise click.exceptions.Exit(max(drifted, _java_classes(result, out, quiet)))
    plan = result.plan
    assert plan is not None
    if diff:
        _show_diff(plan)
    elif dry_run or (write and not quiet):
        verbs = _WOULD if dry_run else _DONE
        for change in plan.changes:
            click.echo(f"{verbs[change.action]} {os.path.join(out, printable(change.path))}")
    report_notes(plan, out, write, {d.path for d in result.drift})
    writes, deletes = len(plan.writes), len(plan.deletes)
    if write:
        if plan.changes:
            summary = f"{writes} written, {deletes} deleted, {len(plan.unchanged)} unchanged"
        else:
            summary = f"nothing changed ({len(plan.unchanged)} files up to date)"
        click.echo(f"{out}: {summary} (targets: {', '.join(result.targets)})")
        raise click.exceptions.Exit(max(drifted, _java_classes(result, out, quiet)))
    if plan.changes:
        click.echo(
            f"{out}: not up to date: {writes} file{'s' if writes != 1 else ''} to write, "
            f"{deletes} to delete",
            err=check and not dry_run and not diff,
        )
    else:
        click.echo(f"{out}: up to date ({len(plan.unchanged)} files)")
    raise click.exceptions.Exit(1 if check and plan.changes else drifted)


def _java_classes(result, out: str, quiet: bool) -> int:
    """Say what the build's compile of the Java components' classes did; 1 when a class does
    not compile (javac's file:line and message), else 0."""
    java = result.java
    if java is None or java.note:  # none, or no JDK: said among the notes
        return 0
    if java.error is not None:
        click.echo(printable(str(java.error)), err=True)
        for line in java.error.said.splitlines():  # each line escaped: none can forge another
            click.echo(f"  {printable(line)}", err=True)
        click.echo(
            f"{out}: the generated files are in place; no Java classes were compiled for these "
            "sources (a container hosting the component stops at start with the same error)",
            err=True,
        )
        return 1
    if java.compiled and not quiet:
        click.echo(f"compiled {os.path.join(out, java.classes)}/ (javac)")
    return 0


_WOULD = {
    "create": "would write",
    "update": "would write",
    "delete": "would delete",
    "move": "would move aside to",
}
_DONE = {"create": "wrote", "update": "wrote", "delete": "deleted", "move": "moved aside to"}


def _list(ctx: click.Context) -> None:
    from acordcs.generator.targets import targets

    for name, made in targets().items():
        click.echo(f"{name:12s} {made.kind:6s} {made.description} ({made.origin})")
    warn_plugins()
    ctx.exit(0)


def _count(target_names: tuple[str, ...]) -> list[str]:
    from acordcs.generator.targets import targets

    wanted = [n for name in target_names for n in name.split(",") if n.strip()]
    return list(targets()) if not wanted or "all" in wanted else wanted


class _Bar:
    """A click progress bar over the build's steps, on standard error (only on a terminal)."""

    def __init__(self, steps: int) -> None:
        self.bar = click.progressbar(length=steps, label="building", file=sys.stderr, width=24)
        self.bar.__enter__()
        self.started = False

    def step(self, label: str) -> None:
        self.bar.label = f"building: {label}"
        if self.started:
            self.bar.update(1)
        else:
            self.bar.render_progress()
        self.started = True

    def close(self) -> None:
        self.bar.__exit__(None, None, None)


def report_notes(plan, out: str, write: bool, explained: Collection[str] = ()) -> None:
    """What a build did (``write``) or would do to the user's files in ``out``: edited generated
    files saved aside, stale edited ones left, orphaned user code (except the files of
    ``explained``, which a drift warning names), regions moved to ``.lost``."""
    from acordcs.generator.paths import READ_LIMIT

    for path, saved in plan.edited.items():
        if path in plan.unread:
            click.echo(
                f"acordcs-gen: {os.path.join(out, printable(path))}: is "
                f"{printable(plan.unread[path])}, which a build does not read (it reads regular "
                f"files of at most {READ_LIMIT // (1024 * 1024)} MiB): taken as edited, "
                f"it {'is' if write else 'would be'} moved aside unread to "
                f"{os.path.join(out, printable(saved))}, and the file regenerated",
                err=True,
            )
            continue
        regions = bool(plan.manifest.files[path].outside)
        what = (
            "lines outside its BEGIN USER/END USER regions were edited" if regions else "was edited"
        )
        click.echo(
            f"acordcs-gen: {os.path.join(out, printable(path))}: {what} since the build that "
            f"wrote it: your version {'is' if write else 'would be'} saved as "
            f"{os.path.join(out, printable(saved))}, and the file regenerated "
            + (
                "(only the lines between a region's markers are yours in this file)"
                if regions
                else "(a generated file is the model's: change the model, or your own code)"
            ),
            err=True,
        )
    for kept in plan.kept:
        click.echo(
            f"acordcs-gen: {os.path.join(out, printable(kept))} is no longer generated but was edited since: "
            "left in place (delete it yourself if it is not needed)",
            err=True,
        )
    # ``explained``: a renamed component's code, which G704 says what to do with
    for orphan in plan.orphaned:
        if orphan in explained:
            continue
        click.echo(
            f"acordcs-gen: {os.path.join(out, printable(orphan))} is your code for "
            f"{printable(plan.manifest.files[orphan].element or 'an element')}, no longer in the model: "
            "kept, no longer used by the generated code (delete it yourself if it is not needed)",
            err=True,
        )
    for path, keys in plan.lost.items():
        click.echo(
            f"acordcs-gen: {os.path.join(out, printable(path))}: your lines in region"
            f"{'s' if len(keys) > 1 else ''} {printable(', '.join(keys))}, whose model element"
            f"{'s are' if len(keys) > 1 else ' is'} no longer in the model, "
            f"{'moved' if write else 'would be moved'} to "
            f"{os.path.join(out, printable(path))}.lost",
            err=True,
        )


def warn_plugins() -> None:
    """The problems met loading other packages' targets, once."""
    from acordcs.generator import targets

    for problem in targets.TARGETS.take_problems():
        click.echo(f"acordcs-gen: warning: {problem}", err=True)


def report_failure(err, command: str = "build") -> None:
    """A build that failed: its diagnostics, their count, and what failed (``command`` names
    the command that ran the build)."""
    for d in err.diagnostics:
        click.echo(d.format_text())
    if err.diagnostics:
        from collections import Counter

        counts = Counter(str(d.severity) for d in err.diagnostics)
        click.echo(
            f"{printable(err.diagnostics[0].file)}: "
            + ", ".join(
                f"{counts[s]} {s}{'s' if counts[s] != 1 else ''}"
                for s in ("error", "warning", "info")
            )
        )
    where = f"{printable(err.location())}: " if err.file else ""  # a newline in a name: escaped
    text = f"{where}error: {err.message}"
    if err.element:
        text += f" [{err.element}]"
    if err.hint:
        text += f" ({err.hint})"
    lines = text.splitlines() or [text]
    click.echo(f"acordcs-gen {command}: {printable(lines[0])}", err=True)
    for line in lines[1:]:
        click.echo(f"  {printable(line)}", err=True)


def _show_diff(plan) -> None:
    import difflib

    for change in plan.changes:
        old = _lines(change.old)
        new = _lines(change.new)
        before = f"a/{change.path}" if change.old is not None else "/dev/null"
        after = f"b/{change.path}" if change.new is not None else "/dev/null"
        for line in difflib.unified_diff(old, new, printable(before), printable(after)):
            click.echo(_escaped(line), nl=not line.endswith("\n"))


def _escaped(line: str) -> str:
    """A diff line as printed: its characters that would move the cursor or reorder the text
    (control, bidi, line separators: what a stylesheet or a model may put in a file) escaped,
    tabs and the line's own end kept."""
    end = "\n" if line.endswith("\n") else ""
    body = line[: len(line) - len(end)]
    return "\t".join(printable(part) for part in body.split("\t")) + end


def _lines(data: bytes | None) -> list[str]:
    if data is None:
        return []
    return data.decode("utf-8", "replace").splitlines(keepends=True)
