"""``build``: model file -> checked model -> descriptor -> targets -> output directory.

1. **Up to date?** When the manifest says the selected targets were built from a model with this
   sha256 by code with these fingerprints, and every file it lists for them is intact, nothing is
   read and nothing is written (``force`` skips this).
2. **Read and validate** (:func:`acordcs.model.reading.read_model`): an error stops the build,
   nothing written.
   Validating includes the rules on the names that generated files and code take (G701, G703:
   :mod:`acordcs.model.generated_names`).
3. **Describe** (:func:`acordcs.generator.describe.describe`, :func:`~acordcs.descriptor.to_xml`).
4. **Transform**: each target runs in memory and hands back its files (a stylesheet's result
   documents too: :mod:`acordcs.generator.xslt`); a target that fails, or files that would leave
   the output directory or collide (G701, G702), stop the build with the output directory
   untouched.
5. **Write** only what changed, each file once and into place, delete stale generated files,
   write the manifest (:mod:`acordcs.generator.writer`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

from acordcs.diagnostics import Diagnostic, Severity, diagnostic
from acordcs.generator.errors import BuildError
from acordcs.generator.manifest import Manifest, ManifestError, read_manifest, sha256
from acordcs.generator.paths import MANIFEST, case_collisions, path_problem, read_bounded
from acordcs.generator.target import NAME_PATTERN, Target
from acordcs.generator.target_context import GeneratedFile, TargetContext
from acordcs.generator.targets import targets
from acordcs.generator.writer import FileChanges, apply, plan

if TYPE_CHECKING:
    from acordcs.descriptor import Application
    from acordcs.generator.java_classes import JavaBuild

Progress = Callable[[str], None]


@dataclass
class BuildResult:
    """What a build did (or, without ``write``, would do). ``up_to_date``: nothing to do, found
    from the manifest alone (the model was not read)."""

    output: Path
    targets: list[str]
    plan: FileChanges | None = None
    up_to_date: bool = False
    written: bool = False
    warnings: list[Diagnostic] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    drift: list = field(default_factory=list)  # acordcs.generator.drift.Drift: the user's code
    application: Application | None = None  # the model described (None: up to date, not read)
    java: JavaBuild | None = None  # the Java components' classes compiled (java target)

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


STYLESHEET_SUFFIXES = (".xsl", ".xslt")


def select(names: Iterable[str] | None, trust: bool = False) -> list[Target]:
    """The targets named (``all`` or nothing: every registered target), in name order. A name
    ending in ``.xsl`` or ``.xslt`` is the path of a stylesheet of the user's: a target named
    after the file (``mine.xsl``), run as a built-in XSLT target is (:func:`stylesheet_target`).
    ``trust`` (``--trust-stylesheet``): the stylesheets not built in run with the user's rights,
    not confined."""
    known = targets()
    wanted = [n.strip() for name in (names or ("all",)) for n in name.split(",") if n.strip()]
    files = [n for n in wanted if n.lower().endswith(STYLESHEET_SUFFIXES)]
    named = [n for n in wanted if n not in files]
    chosen = {t.name: t for t in (known.values() if not named and not files else ())}
    if "all" in named:
        chosen.update(known)
    unknown = [n for n in named if n != "all" and n not in known]
    if unknown:
        raise BuildError(
            f"unknown target{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))}",
            hint=f"targets: {', '.join(known) or 'none'}, or all, or the path of an XSLT 3.0 "
            "stylesheet (a file ending in .xsl or .xslt)",
            exit_code=2,
        )
    chosen.update((n, known[n]) for n in named if n != "all")
    for path in files:
        made = stylesheet_target(path)
        other = chosen.get(made.name)
        if other is not None and other.stylesheet != made.stylesheet:
            raise BuildError(
                f"two targets named {made.name!r}: {path} and {other.stylesheet or other.origin}",
                hint="a stylesheet's target is named after its file: rename one of the files",
                exit_code=2,
            )
        chosen[made.name] = made
    if trust:
        for name, made in chosen.items():
            if made.stylesheet is not None and not _built_in(made):
                chosen[name] = replace(made, trusted=True)
    return [chosen[n] for n in sorted(chosen)]


def _built_in(made: Target) -> bool:
    from acordcs.generator.target import _TRANSFORMS

    return (
        made.origin == "acordcs"
        and made.stylesheet is not None
        and (made.stylesheet.resolve().parent == _TRANSFORMS)
    )


def stylesheet_target(path: str | os.PathLike[str]) -> Target:
    """The target of the user's XSLT 3.0 stylesheet at ``path`` (``-t path/to/mine.xsl``): named
    after the file, not registered; its fingerprint is the stylesheet's bytes (an edited
    stylesheet rebuilds). :class:`BuildError` (exit 2) when the file cannot be read."""
    file = Path(path)
    if not file.is_file():
        raise BuildError(
            f"stylesheet {os.fspath(path)!r} not found (-t names a target, or the path of an XSLT "
            "3.0 stylesheet)",
            hint="give the path of an existing .xsl or .xslt file, or a target of "
            "acordcs-gen build --list",
            exit_code=2,
        )
    if not NAME_PATTERN.match(file.name):
        raise BuildError(
            f"stylesheet {os.fspath(path)!r}: its file name cannot name a target (letters, digits, "
            "'_', '.' and '-', not starting with '.' or '-')",
            hint="rename the file",
            exit_code=2,
        )
    return Target(file.name, f"the stylesheet {file}", stylesheet=file.resolve(), origin=str(file))


def build(
    model: str | os.PathLike[str],
    output: str | os.PathLike[str],
    target_names: Iterable[str] | None = None,
    *,
    write: bool = True,
    force: bool = False,
    check: bool = False,
    drift: bool = False,
    progress: Progress | None = None,
    trust_stylesheets: bool = False,
) -> BuildResult:
    """Build ``target_names`` (default: all) of ``model`` into ``output``. With ``write`` False
    nothing is written: the result's plan says what would change (``--dry-run``, ``--diff``).
    ``check`` (``--check``) writes nothing either and trusts the manifest only to say which files
    are generated: the targets always run (as with ``force``) and their bytes are compared with
    the files on disk; a manifest that cannot be read is an error. ``drift`` (``--strict``):
    compare the user's classes with the model even when nothing else is to be done (a build
    that reads the model always does). ``trust_stylesheets`` (``--trust-stylesheet``): the
    stylesheets not built in run with the user's rights instead of confined. Raises :class:`BuildError` (nothing written) when the
    build cannot be done."""
    source = os.fspath(model)
    out = Path(output)
    chosen = select(target_names, trust=trust_stylesheets)
    result = BuildResult(out, [t.name for t in chosen])
    if check:
        write, force = False, True
    try:
        found = _build(source, out, chosen, result, write, force, check, progress)
        if drift and found.up_to_date and any(t.name == "python" for t in chosen):
            _find_drift(out, None, found)
        if write and any(t.name == "java" for t in chosen):
            _compile_java(out, found)
        return found
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
    check: bool,
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
        if check:
            raise BuildError(
                f"{out / MANIFEST} cannot be used: {err}",
                hint="which files of the directory are generated is unknown: build without "
                "--check to write the manifest again (no file is then deleted or overwritten)",
            ) from None
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
    everything = registered <= set(fingerprints)
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
    from acordcs.generator.describe import describe

    try:
        app = describe(reading.architecture)
        data = to_xml(app)
    except DescriptorError as err:
        raise BuildError(
            err.message, file=err.file or source, line=err.line, hint=err.hint
        ) from None
    result.application = app
    located = reading.uml.elements
    if any(t.name == "python" for t in chosen):
        _find_drift(out, app, result)

    def locate(element_id: str) -> int:
        return getattr(located.get(element_id), "line", 0) or 0

    files: list[GeneratedFile] = []
    for made in chosen:  # in memory: nothing reaches the output before every target succeeded
        step(f"target {made.name}")
        context = TargetContext(made.name, app, data, source, locate=locate)
        _run(made, context)
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


def _compile_java(out: Path, result: BuildResult) -> None:
    """The Java components' classes, compiled into the output (:mod:`.java_classes`) once the
    files are written: a note when no JDK is found, ``result.java.error`` when one does not
    compile."""
    from acordcs.generator.java_classes import compile_java_classes

    manifest = read_manifest(out)
    app = result.application or _built_application(out, manifest)
    if manifest is None or app is None:
        return
    result.java = compile_java_classes(out, app, manifest)
    if result.java is not None and result.java.note:
        result.notes.append(result.java.note)


def _built_application(out: Path, manifest: Manifest | None) -> Application | None:
    """The application the output's Python package was last built from (its descriptor), or
    None (no package, or a descriptor that does not read)."""
    from acordcs.generator.drift import previous_application

    package = _built_package(manifest)
    return previous_application(out, package) if package else None


def _built_package(manifest: Manifest | None) -> str | None:
    """The Python package the manifest lists files of (None: none)."""
    names = {rel.split("/", 1)[0] for rel in (manifest.files if manifest else ()) if "/" in rel}
    return next((n for n in sorted(names) if n.endswith("_app")), None)


def _find_drift(out: Path, app: Application | None, result: BuildResult) -> None:
    """The user's classes against the model (:mod:`acordcs.generator.drift`), and compiled as a
    container's start compiles them (G705), before anything is written: the package's descriptor on disk is still the previous build's. ``app`` None: the
    output is up to date, the descriptor on disk is the model's."""
    from acordcs.generator.drift import (
        as_diagnostics,
        find_drift,
        not_compiling,
        previous_application,
    )
    from acordcs.generator.manifest import read_manifest
    from acordcs.generator.targets.python import package_name

    if app is None:
        manifest = read_manifest(out)
        package = _built_package(manifest)
        current = _built_application(out, manifest)
        if current is None or package is None:
            return
        result.drift = find_drift(out, package, None, current)
        result.drift += not_compiling(out, package, current)
    else:
        from acordcs.generator.java_drift import find_java_drift

        package = package_name(app.name)
        previous = previous_application(out, package)
        result.drift = find_drift(out, package, previous, app)
        result.drift += find_java_drift(out, previous, app)
        result.drift += not_compiling(out, package, app)
    result.warnings += as_diagnostics(result.drift, out)


def _intact(out: Path, old: Manifest, fingerprints: dict[str, str], model_sha: str) -> bool:
    """Whether ``out`` holds what the selected targets would make of this model with this code,
    by the manifest: same model, same fingerprints, every listed file there with its sha256."""
    for name, fingerprint in fingerprints.items():
        record = old.targets.get(name)
        if record != {"fingerprint": fingerprint, "model_sha256": model_sha}:
            return False
    root = os.fspath(out)
    for rel, entry in old.files.items():
        if entry.target not in fingerprints:
            continue
        path = os.path.join(root, rel)  # strings: thousands of files, no Path objects
        if entry.user:  # the user's: edited, as expected; a deleted one is written again
            if not os.path.isfile(path):
                return False
            continue
        try:  # a FIFO or a huge file: not intact, found at once (the plan reports it)
            if sha256(read_bounded(path)) != entry.sha256:
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
    for f in by_path.values():  # a file where another file needs a directory
        parts = f.path.split("/")
        for n in range(1, len(parts)):
            other = by_path.get("/".join(parts[:n]))
            if other is not None:
                found.append(
                    diagnostic(
                        "G702",
                        f"target {f.target} would write {f.path!r} inside {other.path!r}, a file "
                        f"target {other.target} writes (from {other.element or '?'}); rename one "
                        "element",
                        **where(f),
                    )
                )
                break
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
