"""Putting a build's files into the output directory: only what changed, nothing of the user's.

:func:`plan` compares the generated files with the output directory and the previous manifest:

- a file whose bytes are already there is left alone (its mtime too);
- a new or changed file is written; an existing file the previous builds did not write (it is not
  in the manifest) is the user's and is never overwritten: the build stops instead;
- a file the manifest lists, made by a target of this build, that the build no longer makes is
  stale and deleted, unless it was edited since (its sha256 is not the manifest's): then it is
  left in place and reported;
- a path through a symbolic link, or onto a directory, is refused;
- a file emitted ``once`` (generation gap: the class a user implements) is written only when
  absent; from then on it is the user's: recorded in the manifest as such (``user``), never
  overwritten, never deleted. When the model no longer makes it, it stays, still recorded, and
  is reported as orphaned (:attr:`Plan.orphaned`) by every build that runs the targets, until the
  user removes it;
- a file with protected regions (``regions``) gets, in each region, the text of the same region
  of the file on disk (:func:`acordcs.codegen.regions.merge`); the regions the model no longer
  makes are appended to ``<file>.lost`` (:attr:`Plan.lost`), a file of the user's from then on.
  Regions that cannot be read (a key twice, a region not closed) stop the build.

:func:`apply` writes each file to a temporary name beside it and renames it over the old one (a
reader never sees half a file), deletes the stale files, removes directories left empty by that,
and writes the manifest last.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from acordcs.codegen.context import GeneratedFile
from acordcs.codegen.errors import BuildError
from acordcs.codegen.manifest import Entry, Manifest, sha256
from acordcs.codegen.paths import MANIFEST


@dataclass
class Change:
    path: str
    action: str  # "create", "update", "delete"
    old: bytes | None
    new: bytes | None
    executable: bool = False


@dataclass
class Plan:
    changes: list[Change] = field(default_factory=list)
    unchanged: list[str] = field(default_factory=list)
    kept: list[str] = field(default_factory=list)  # stale but edited by the user: left in place
    orphaned: list[str] = field(default_factory=list)  # user files the model no longer makes
    lost: dict[str, list[str]] = field(default_factory=dict)  # file -> keys of regions moved out
    manifest: Manifest = field(default_factory=Manifest)
    manifest_bytes: bytes = b""
    manifest_changed: bool = True

    @property
    def writes(self) -> list[Change]:
        return [c for c in self.changes if c.action != "delete"]

    @property
    def deletes(self) -> list[Change]:
        return [c for c in self.changes if c.action == "delete"]


def _through_link(output: Path, rel: str) -> str | None:
    """The first component of ``rel`` under ``output`` that is a symbolic link, or None."""
    current = output
    for part in rel.split("/"):
        current = current / part
        if current.is_symlink():
            return current.relative_to(output).as_posix()
    return None


def _existing(output: Path, rel: str) -> bytes | None:
    link = _through_link(output, rel)
    if link is not None:
        raise BuildError(
            f"{output / rel}: {link} is a symbolic link; generated files are never written or "
            "deleted through links",
            hint="replace the link by a directory, or choose another output directory",
            exit_code=2,
        )
    path = output / rel
    try:
        with open(path, "rb") as handle:
            return handle.read()
    except FileNotFoundError:
        return None
    except NotADirectoryError:
        raise BuildError(
            f"{path}: a file stands where a directory of generated files must be",
            hint="move that file away, or choose another output directory",
            exit_code=2,
        ) from None
    except IsADirectoryError:
        raise BuildError(
            f"{path}: a directory stands where a generated file must be written",
            hint="move it away, or choose another output directory",
            exit_code=2,
        ) from None
    except OSError as err:
        raise BuildError(f"{path}: cannot read it: {err.strerror}", exit_code=2) from None


def plan(
    output: Path,
    files: list[GeneratedFile],
    old: Manifest | None,
    new: Manifest,
    selected: set[str],
) -> Plan:
    """What must change in ``output`` for it to hold ``files`` (made by the ``selected`` targets);
    ``new`` is the manifest to write, its ``files`` filled in here."""
    result = Plan(manifest=new)
    previous = old.files if old else {}
    made = {f.path for f in files}
    for f in files:
        current = _existing(output, f.path)
        if f.regions and current is not None and not f.once:
            f = _merge_regions(output, f, current, result)
        new.files[f.path] = Entry(sha256(f.data), f.target, f.element, f.ids, f.once)
        if current == f.data or (f.once and current is not None):  # once: the user's, as is
            result.unchanged.append(f.path)
        elif current is None:
            result.changes.append(Change(f.path, "create", None, f.data, f.executable))
        elif f.path in previous and not previous[f.path].user:
            result.changes.append(Change(f.path, "update", current, f.data, f.executable))
        else:
            raise BuildError(
                f"{output / f.path} exists and this build did not write it (it is not in "
                f"{MANIFEST}): it would be overwritten by target {f.target}",
                hint="move your file away, or choose another output directory; a build never "
                "overwrites a file it did not write",
            )
    for path, entry in sorted(previous.items()):
        if path in made:
            continue
        if entry.target not in selected:  # another target's file: kept, and still listed
            new.files[path] = entry
            continue
        current = _existing(output, path)
        if current is None:
            continue
        if entry.user:  # the user's code for an element gone from the model: never deleted
            new.files[path] = entry
            result.orphaned.append(path)
            continue
        if sha256(current) == entry.sha256:
            result.changes.append(Change(path, "delete", current, None))
        else:
            result.kept.append(path)
    result.changes.sort(key=lambda c: c.path)
    result.manifest_bytes = new.to_bytes()
    try:
        result.manifest_changed = (output / MANIFEST).read_bytes() != result.manifest_bytes
    except OSError:
        result.manifest_changed = True
    return result


def _merge_regions(output: Path, f: GeneratedFile, current: bytes, result: Plan) -> GeneratedFile:
    """``f`` with the user's region text of ``current``; lost regions planned into ``.lost``."""
    from dataclasses import replace

    from acordcs.codegen.regions import RegionError, lost_text, merge

    try:
        merged, lost = merge(f.regions, f.data.decode("utf-8"), current.decode("utf-8"))
    except UnicodeDecodeError:
        raise BuildError(
            f"{output / f.path}: not UTF-8: its protected regions cannot be read",
            hint="save it as UTF-8, or move it away (the build writes it again)",
        ) from None
    except RegionError as err:
        raise BuildError(
            f"{output / f.path}: {err}",
            hint="fix the BEGIN USER/END USER lines (each key once, each region closed), or move "
            "the file away (the build writes it again, with empty regions)",
        ) from None
    if lost:
        path = f.path + ".lost"
        before = _existing(output, path)
        text = (before or b"") + lost_text(f.regions, f.path, lost).encode("utf-8")
        result.changes.append(Change(path, "update" if before else "create", before, text))
        result.lost[f.path] = list(lost)
    return replace(f, data=merged.encode("utf-8"))


def _write(path: Path, data: bytes, executable: bool = False) -> None:
    temporary = path.with_name(f".{path.name}.acordcs-tmp")
    try:
        mode = 0o777 if executable else 0o666  # less the umask, as open() applies it
        temporary.unlink(missing_ok=True)  # a leftover keeps its mode; a link is not followed
        descriptor = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, mode)
        with open(descriptor, "wb") as handle:
            handle.write(data)
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def apply(output: Path, result: Plan) -> None:
    """Carry out ``result`` in ``output`` (created if missing)."""
    done: list[str] = []
    try:
        output.mkdir(parents=True, exist_ok=True)
        for change in result.changes:
            path = output / change.path
            if change.action == "delete":
                path.unlink(missing_ok=True)
                _prune(output, path.parent)
            else:
                path.parent.mkdir(parents=True, exist_ok=True)
                assert change.new is not None
                _write(path, change.new, change.executable)
            done.append(change.path)
        if result.manifest_changed:
            _write(output / MANIFEST, result.manifest_bytes)
    except OSError as err:
        where = err.filename or output
        raise BuildError(
            f"{where}: cannot write: {err.strerror}"
            + (f" (already done: {', '.join(done)})" if done else ""),
            hint="check the output directory's permissions and free space, then build again: "
            "the next build finishes the job",
            exit_code=2,
        ) from None


def _prune(output: Path, directory: Path) -> None:
    """Remove ``directory`` and its parents up to ``output`` (excluded) while they are empty."""
    while directory != output and output in directory.parents:
        try:
            directory.rmdir()
        except OSError:  # not empty, or not ours to remove
            return
        directory = directory.parent
