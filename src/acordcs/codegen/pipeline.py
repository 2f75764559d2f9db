"""``build``: model file -> checked model -> descriptor -> targets -> output directory.

1. **Up to date?** When the manifest says the selected targets were built from a model with this
   sha256 by code with these fingerprints, and every file it lists for them is intact, nothing is
   read and nothing is written (``force`` skips this).
2. **Read and validate** (:func:`acordcs.model.reading.read_model`): an error stops the build,
   nothing written.
3. **Describe** (:func:`acordcs.model.describe.describe`, :func:`~acordcs.descriptor.to_xml`), and check
   every name that may become part of a path (G701).
4. **Transform**: each target runs into a temporary directory and hands back its files; a target
   that fails, or files that would leave the output directory or collide (G701, G702), stop the
   build with the output directory untouched.
5. **Write** only what changed, delete stale generated files, write the manifest
   (:mod:`acordcs.codegen.writer`).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from acordcs.codegen.context import GeneratedFile, TargetContext
from acordcs.codegen.errors import BuildError
from acordcs.codegen.manifest import Manifest, ManifestError, read_manifest, sha256
from acordcs.codegen.paths import (
    MANIFEST,
    NAME_BYTES,
    RULE,
    case_collisions,
    path_problem,
    segment_problem,
)
from acordcs.codegen.registry import Target, targets
from acordcs.codegen.writer import Plan, apply, plan
from acordcs.diagnostics import Diagnostic, Severity, diagnostic

Progress = Callable[[str], None]


@dataclass
class BuildResult:
    """What a build did (or, without ``write``, would do). ``up_to_date``: nothing to do, found
    from the manifest alone (the model was not read)."""

    output: Path
    targets: list[str]
    plan: Plan | None = None
    up_to_date: bool = False
    written: bool = False
    warnings: list[Diagnostic] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def changed(self) -> bool:
        """Whether the output's generated files differ from what the model makes."""
        return bool(self.plan and self.plan.changes)


@cache
def toolchain_digest() -> str:
    """A digest of acordcs's own code and data files (path, size, mtime): part of every target's
    fingerprint, so that a changed toolchain rebuilds. Stat only: hashing the 850 KB of source on
    every no-op rebuild would cost more than the rebuild."""
    import hashlib

    import acordcs

    root = os.path.dirname(acordcs.__file__)
    digest = hashlib.sha256()
    for directory, subdirectories, names in os.walk(root):
        subdirectories[:] = sorted(d for d in subdirectories if d != "__pycache__")
        for name in sorted(names):
            if name.endswith((".py", ".xsl", ".xslt", ".xsd", ".lark", ".ecore")):
                path = os.path.join(directory, name)
                info = os.stat(path)
                digest.update(
                    f"{os.path.relpath(path, root)}\0{info.st_size}\0{info.st_mtime_ns}\0".encode()
                )
    return digest.hexdigest()


def select(names: Iterable[str] | None) -> list[Target]:
    """The targets named (``all`` or nothing: every registered target), in name order."""
    known = targets()
    wanted = [n.strip() for name in (names or ("all",)) for n in name.split(",") if n.strip()]
    if not wanted or "all" in wanted:
        return list(known.values())
    unknown = [n for n in wanted if n not in known]
    if unknown:
        raise BuildError(
            f"unknown target{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))}",
            hint=f"targets: {', '.join(known) or 'none'}, or all",
            exit_code=2,
        )
    return [known[n] for n in sorted(set(wanted))]


def build(
    model: str | os.PathLike[str],
    output: str | os.PathLike[str],
    target_names: Iterable[str] | None = None,
    *,
    write: bool = True,
    force: bool = False,
    progress: Progress | None = None,
) -> BuildResult:
    """Build ``target_names`` (default: all) of ``model`` into ``output``. With ``write`` False
    nothing is written: the result's plan says what would change (``--check``, ``--dry-run``,
    ``--diff``). Raises :class:`BuildError` (nothing written) when the build cannot be done."""
    source = os.fspath(model)
    out = Path(output)
    chosen = select(target_names)
    result = BuildResult(out, [t.name for t in chosen])
    try:
        return _build(source, out, chosen, result, write, force, progress)
    except BuildError as err:
        err.notes = result.notes + result.messages
        raise


def _build(
    source: str,
    out: Path,
    chosen: list[Target],
    result: BuildResult,
    write: bool,
    force: bool,
    progress: Progress | None,
) -> BuildResult:
    step = progress or (lambda _label: None)
    if out.exists() and not out.is_dir():
        raise BuildError(
            f"{out} is not a directory",
            hint="give -o/--output a directory (created if missing)",
            exit_code=2,
        )
    try:
        old = read_manifest(out)
    except ManifestError as err:
        result.notes.append(
            f"{out / MANIFEST} is ignored ({err}): no file of the directory is known to be "
            "generated, so none is deleted or overwritten"
        )
        old = None
    try:
        if not os.path.isfile(source):  # a named pipe would block here: read_model reports it
            raise FileNotFoundError(source)
        with open(source, "rb") as handle:
            model_sha = sha256(handle.read())
    except OSError:
        model_sha = ""  # read_model reports it
    fingerprints = {t.name: t.fingerprint(toolchain_digest()) for t in chosen}
    registered = set(targets())
    everything = set(fingerprints) == registered
    name = os.path.basename(source) or source  # what headers name
    if (
        not force
        and old is not None
        and model_sha
        and old.model == name
        and _intact(out, old, fingerprints, model_sha)
        and not (everything and {e.target for e in old.files.values()} - registered)
    ):
        result.up_to_date = True
        return result

    step("reading and validating the model")
    from acordcs.model.reading import read_model

    reading = read_model(source)
    if reading.unreadable or reading.worst() == Severity.ERROR:
        raise BuildError(
            "the model could not be read; nothing was built"
            if reading.unreadable
            else "the model has errors; nothing was built",
            file=source,
            diagnostics=reading.diagnostics,
            exit_code=2 if reading.unreadable else 1,
            hint="fix what is reported (acordcs-gen validate shows the same), then build again",
        )
    result.warnings = list(reading.diagnostics)

    step("describing the application")
    from acordcs.descriptor import DescriptorError, to_xml
    from acordcs.model.describe import describe

    try:
        app = describe(reading.architecture)
        data = to_xml(app)
    except DescriptorError as err:
        raise BuildError(
            err.message, file=err.file or source, line=err.line, hint=err.hint
        ) from None
    located = reading.uml.elements

    def locate(element_id: str) -> int:
        return getattr(located.get(element_id), "line", 0) or 0

    _check_names(app, source, locate)

    files: list[GeneratedFile] = []
    with tempfile.TemporaryDirectory(prefix="acordcs-build-") as scratch:

        def run(made: Target) -> TargetContext:
            workdir = Path(scratch, made.name)
            workdir.mkdir()
            context = TargetContext(made.name, app, data, source, workdir, locate=locate)
            _run(made, context)
            return context

        for made in chosen:
            step(f"target {made.name}")
            context = run(made)
            files += context.files
            result.messages += [f"target {made.name}: {m}" for m in context.messages]
    _check_files(files, source, locate, located)

    step("comparing with the output directory")
    selected = set(fingerprints)
    if old is not None and everything:  # files of targets no longer installed are stale
        selected |= {e.target for e in old.files.values()} - registered
    new = Manifest(name, model_sha)
    if old is not None:
        new.targets = {k: v for k, v in old.targets.items() if k not in selected}
    for name, fingerprint in fingerprints.items():
        new.targets[name] = {"fingerprint": fingerprint, "model_sha256": model_sha}
    result.plan = plan(out, files, old, new, selected)
    if write:
        step("writing")
        write_out(result)
    return result


def write_out(result: BuildResult) -> None:
    """Write what a build made without writing (``write=False``) into its output directory, as
    ``build`` does last: what a caller that looks before writing (``acordcs-gen update``) calls."""
    if result.plan is not None and (result.plan.changes or result.plan.manifest_changed):
        apply(result.output, result.plan)
        result.written = True


def _intact(out: Path, old: Manifest, fingerprints: dict[str, str], model_sha: str) -> bool:
    """Whether ``out`` holds what the selected targets would make of this model with this code,
    by the manifest: same model, same fingerprints, every listed file there with its sha256."""
    for name, fingerprint in fingerprints.items():
        record = old.targets.get(name)
        if record != {"fingerprint": fingerprint, "model_sha256": model_sha}:
            return False
    for rel, entry in old.files.items():
        if entry.target not in fingerprints:
            continue
        if entry.user:  # the user's: edited, as expected; a deleted one is written again
            if not (out / rel).is_file():
                return False
            continue
        try:
            with open(out / rel, "rb") as handle:
                if sha256(handle.read()) != entry.sha256:
                    return False
        except OSError:
            return False
    return True


def _run(made: Target, context: TargetContext) -> None:
    try:
        made.run(context)
    except BuildError:
        raise
    except Exception as err:
        raise BuildError(
            f"target {made.name} failed: {type(err).__name__}: {err}",
            file=context.source,
            hint=f"nothing was written; this is a fault of target {made.name} ({made.origin}): "
            "report it, or build the other targets with --target",
        ) from None


def _elements(app) -> list[tuple[str, str, str, str]]:
    """(kind, name, id, qualified name) of every described element, the application first."""
    out = [("model", app.name, "", app.name)]
    for kind, items in (
        ("container", app.containers),
        ("component", app.components),
        ("connection", app.connections),
        ("monitor", app.monitors),
        ("policy set", app.policy_sets),
    ):
        out += [(kind, e.name, e.id, e.qualified_name) for e in items]
        if kind == "component":
            out += [("port", p.name, p.id, p.qualified_name) for c in items for p in c.ports]
        if kind == "policy set":
            out += [("policy", p.name, p.id, p.qualified_name) for s in items for p in s.policies]
    return out


def _what(kind: str, name: str, qualified: str) -> str:
    return f"the {kind}" if qualified == name else f"{kind} {qualified!r}"


def _check_names(app, source: str, locate: Callable[[str], int]) -> None:
    """Every name a target may put into a path is a file name (G701), checked before any target
    runs: a stylesheet's result documents are written by Saxon, out of our hands."""
    found = []
    for kind, name, element_id, qualified in _elements(app):
        problem = segment_problem(name, NAME_BYTES)
        if problem:
            found.append(
                diagnostic(
                    "G701",
                    f"the name {name!r} of {_what(kind, name, qualified)} cannot become part of a "
                    f"file name: {problem}; rename it ({RULE})",
                    file=source,
                    line=locate(element_id) if element_id else 0,
                    element=qualified,
                    xmi_id=element_id or None,
                )
            )
    if found:
        raise BuildError(
            f"{len(found)} model name{'s' if len(found) > 1 else ''} cannot become part of a "
            "file name; nothing was built",
            file=source,
            diagnostics=found,
        )


def _check_files(
    files: list[GeneratedFile], source: str, locate: Callable[[str], int], located: dict
) -> None:
    """Every generated path stays inside the output directory (G701) and names its own file
    (G702: not twice, not differing only in case)."""
    found = []

    def where(f: GeneratedFile) -> dict:
        first = f.ids[0] if f.ids else None
        return {
            "file": source,
            "line": locate(first) if first else 0,
            "element": f.element or None,
            "xmi_id": first,
        }

    by_path: dict[str, GeneratedFile] = {}
    for f in files:
        problem = path_problem(f.path)
        if problem:
            found.append(
                diagnostic(
                    "G701",
                    f"target {f.target} would write {f.path!r}: {problem}; rename the element",
                    **where(f),
                )
            )
        elif f.path in by_path:
            other = by_path[f.path]
            found.append(
                diagnostic(
                    "G702",
                    f"targets {other.target} and {f.target} would both write {f.path!r} (from "
                    f"{other.element or '?'} and {f.element or '?'}); rename one element",
                    **where(f),
                )
            )
        else:
            by_path[f.path] = f
    for first, second in case_collisions(by_path):
        f = by_path[second]
        found.append(
            diagnostic(
                "G702",
                f"{first!r} and {second!r} differ only in case: one file on case-insensitive "
                f"file systems (macOS, Windows); rename {by_path[first].element or first!r} or "
                f"{f.element or second!r}",
                **where(f),
            )
        )
    if found:
        raise BuildError(
            "generated files would collide or leave the output directory; nothing was written",
            file=source,
            diagnostics=found,
        )
