"""Putting a build's files into the output directory: only what changed, nothing of the user's.

:func:`plan` compares the generated files with the output directory and the previous manifest:

- a file whose bytes are already there is left alone (its mtime too);
- a new or changed file is written; an existing file the previous builds did not write (it is not
  in the manifest) is the user's and is never overwritten: the build stops instead;
- a generated file edited since the build that wrote it (its bytes are not the manifest's) is
  saved as ``<file>.edited`` (``.edited.2``... when taken) before it is replaced, and reported
  (:attr:`FileChanges.edited`); for a file with protected regions, only its lines outside the regions
  count (``outside_sha256`` in the manifest);
- a file the manifest lists, made by a target of this build, that the build no longer makes is
  stale and deleted, unless it was edited since (its sha256 is not the manifest's): then it is
  left in place and reported;
- a user's file is never deleted: one the manifest records as ``user``, or whose header says it
  is the user's (:func:`acordcs.generator.headers.is_users`), whatever the manifest says;
- a path through a symbolic link, or onto a directory, is refused;
- a file emitted ``once`` (generation gap: the class a user implements) is written only when
  absent; from then on it is the user's: recorded in the manifest as such (``user``), never
  overwritten, never deleted. When the model no longer makes it, it stays, still recorded, and
  is reported as orphaned (:attr:`FileChanges.orphaned`) by every build that runs the targets, until the
  user removes it;
- a file with protected regions (``regions``) gets, in each region, the text of the same region
  of the file on disk (:func:`acordcs.generator.regions.merge`); the regions the model no longer
  makes are appended to ``<file>.lost`` (:attr:`FileChanges.lost`), a file of the user's from then on.
  Regions that cannot be read (a key twice, a region not closed) stop the build.

:func:`apply` writes every file once, into place. An output directory that does not exist yet is
written whole under a temporary name beside it, then renamed: it appears complete or not at all.
In an existing one, each file goes to a temporary name beside it and is renamed over the old one
(a reader never sees half a file); then the stale files are deleted, directories left empty by
that removed, and the manifest written last.
"""

from __future__ import annotations

import errno
import os
import secrets
import shutil
from dataclasses import dataclass, field, replace
from pathlib import Path

from acordcs.generator.errors import BuildError
from acordcs.generator.headers import is_users
from acordcs.generator.manifest import Entry, Manifest, sha256
from acordcs.generator.paths import MANIFEST, Unreadable, read_bounded
from acordcs.generator.target_context import GeneratedFile


@dataclass
class Change:
    path: str
    action: str  # "create", "update", "delete", "move" (``source`` renamed to ``path``, unread)
    old: bytes | None
    new: bytes | None
    executable: bool = False
    source: str = ""


@dataclass
class FileChanges:
    changes: list[Change] = field(default_factory=list)
    unchanged: list[str] = field(default_factory=list)
    kept: list[str] = field(default_factory=list)  # stale but edited by the user: left in place
    orphaned: list[str] = field(default_factory=list)  # user files the model no longer makes
    lost: dict[str, list[str]] = field(default_factory=dict)  # file -> keys of regions moved out
    edited: dict[str, str] = field(default_factory=dict)  # generated file edited -> where saved
    unread: dict[str, str] = field(default_factory=dict)  # not a regular file, or too large: what
    manifest: Manifest = field(default_factory=Manifest)
    manifest_bytes: bytes = b""
    manifest_changed: bool = True
    fresh: bool = False  # the output directory does not exist: written whole, then renamed

    @property
    def writes(self) -> list[Change]:
        return [c for c in self.changes if c.action != "delete"]

    @property
    def deletes(self) -> list[Change]:
        return [c for c in self.changes if c.action == "delete"]


class _Disk:
    """Reads the output directory's files, refusing any path through a symbolic link (each
    directory is looked at once)."""

    def __init__(self, output: Path) -> None:
        self.output = output
        self.checked: dict[str, str | None] = {"": None}  # directory -> first link in it, or None

    def _link_in(self, directory: str) -> str | None:
        if directory not in self.checked:
            parent, _, _ = directory.rpartition("/")
            found = self._link_in(parent)
            if found is None and (self.output / directory).is_symlink():
                found = directory
            self.checked[directory] = found
        return self.checked[directory]

    def read(self, rel: str) -> bytes | None:
        directory, _, _ = rel.rpartition("/")
        link = self._link_in(directory)
        path = self.output / rel
        if link is None and path.is_symlink():
            link = rel
        if link is not None:
            raise BuildError(
                f"{path}: {link} is a symbolic link; generated files are never written or "
                "deleted through links",
                hint="replace the link by a directory, or choose another output directory",
                exit_code=2,
            )
        try:  # never waits (a FIFO), never reads more than READ_LIMIT: Unreadable for the caller
            return read_bounded(path)
        except FileNotFoundError:
            return None
        except Unreadable as err:
            if err.what != "a directory":
                raise
            raise BuildError(
                f"{path}: a directory stands where a generated file must be written",
                hint="move it away, or choose another output directory",
                exit_code=2,
            ) from None
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
) -> FileChanges:
    """What must change in ``output`` for it to hold ``files`` (made by the ``selected`` targets);
    ``new`` is the manifest to write, its ``files`` filled in here."""
    result = FileChanges(manifest=new, fresh=not os.path.lexists(output))
    disk = _Disk(output)
    previous = old.files if old else {}
    made = {f.path for f in files}
    for f in files:
        try:
            current = None if result.fresh else disk.read(f.path)
        except Unreadable as err:
            _unread(disk, f, err.what, previous.get(f.path), made, result)
            continue
        before = previous.get(f.path)
        outside = ""
        if f.regions and not f.once:
            f, outside = _merge_regions(disk, f, current, before, made, result)
        new.files[f.path] = Entry(sha256(f.data), f.target, f.element, f.ids, f.once, outside)
        if current == f.data or (f.once and current is not None):  # once: the user's, as is
            result.unchanged.append(f.path)
        elif current is None:
            result.changes.append(Change(f.path, "create", None, f.data, f.executable))
        elif before is not None and not before.user:
            if not f.regions and sha256(current) != before.sha256:
                _save_edited(disk, f.path, current, made, result)
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
        try:
            current = None if result.fresh else disk.read(path)
        except Unreadable:  # not read, so not known to be intact: left, as an edited one is
            current = b""
            if not entry.user:
                result.kept.append(path)
                continue
        if current is None:
            continue
        if entry.user or is_users(current):  # the user's code: never deleted
            new.files[path] = replace(entry, user=True)
            result.orphaned.append(path)
        elif sha256(current) == entry.sha256:
            result.changes.append(Change(path, "delete", current, None))
        else:
            result.kept.append(path)
    result.changes.sort(key=lambda c: (c.path, c.action))
    result.manifest_bytes = new.to_bytes()
    if result.fresh:
        result.manifest_changed = True
    else:
        try:
            result.manifest_changed = read_bounded(output / MANIFEST) != result.manifest_bytes
        except OSError:
            result.manifest_changed = True
    return result


def _unread(
    disk: _Disk,
    f: GeneratedFile,
    what: str,
    before: Entry | None,
    made: set[str],
    result: FileChanges,
) -> None:
    """Plan ``f`` where the output holds, at its path, what a build does not read (``what``: a
    FIFO, a device, a file over READ_LIMIT). The user's file (``once``) is left as it is; a
    generated one is taken as edited: renamed aside, unread, to ``<path>.edited`` (or the first
    ``.edited.N`` free), and ``f`` written anew; a file no build wrote stops the build."""
    outside = ""
    if f.regions and not f.once:
        f, outside = _merge_regions(disk, f, None, before, made, result)
    result.manifest.files[f.path] = Entry(
        sha256(f.data), f.target, f.element, f.ids, f.once, outside
    )
    if f.once:
        result.unchanged.append(f.path)
        return
    if before is None or before.user:
        raise BuildError(
            f"{disk.output / f.path} exists ({what}) and this build did not write it (it is not "
            f"in {MANIFEST}): it would be replaced by target {f.target}",
            hint="move it away, or choose another output directory; a build never overwrites a "
            "file it did not write",
        )
    planned = {c.path for c in result.changes}
    for n in range(1, 1000):
        name = f"{f.path}.edited" + (f".{n}" if n > 1 else "")
        if name in made or name in planned or os.path.lexists(disk.output / name):
            continue
        result.changes.append(Change(name, "move", None, None, source=f.path))
        result.changes.append(Change(f.path, "create", None, f.data, f.executable))
        result.edited[f.path] = name
        result.unread[f.path] = what
        return
    raise BuildError(
        f"{disk.output / f.path} is {what} and {f.path}.edited to .edited.999 are taken: nowhere "
        "to move it before it is regenerated",
        hint="move the .edited files away, then build again",
    )


def _save_edited(disk: _Disk, path: str, data: bytes, made: set[str], result: FileChanges) -> None:
    """Plan ``data`` (a generated file as the user edited it) into ``<path>.edited``, or the first
    ``.edited.N`` not taken; nothing to write when one of them already holds these bytes."""
    planned = {c.path for c in result.changes}
    for n in range(1, 1000):
        name = f"{path}.edited" + (f".{n}" if n > 1 else "")
        if name in made or name in planned:
            continue
        try:
            there = disk.read(name)
        except Unreadable:  # taken, by something that is not a copy of this one
            continue
        if there is None:
            result.changes.append(Change(name, "create", None, data))
        elif there != data:
            continue
        result.edited[path] = name
        return
    raise BuildError(
        f"{disk.output / path} was edited since the last build and {path}.edited.2 to .999 are "
        "taken: nowhere to save it before it is regenerated",
        hint="move the .edited files away, then build again",
    )


def _merge_regions(
    disk: _Disk,
    f: GeneratedFile,
    current: bytes | None,
    before: Entry | None,
    made: set[str],
    result: FileChanges,
) -> tuple[GeneratedFile, str]:
    """``f`` with the user's region text of ``current`` (lost regions planned into ``.lost``;
    lines edited outside the regions saved as ``.edited``), and the sha256 of its lines outside
    its regions."""
    from acordcs.generator.regions import RegionError, lost_text, merge, outside

    if current is not None:
        try:
            text = current.decode("utf-8")
            merged, lost = merge(f.regions, f.data.decode("utf-8"), text)
            edited = bool(before and before.outside) and (
                sha256(outside(f.regions, text).encode("utf-8")) != before.outside
            )
        except UnicodeDecodeError:
            raise BuildError(
                f"{disk.output / f.path}: not UTF-8: its protected regions cannot be read",
                hint="save it as UTF-8, or move it away (the build writes it again)",
            ) from None
        except RegionError as err:
            raise BuildError(
                f"{disk.output / f.path}: {err}",
                hint="fix the BEGIN USER/END USER lines (each key once, each region closed), or "
                "move the file away (the build writes it again, with empty regions)",
            ) from None
        except ValueError as err:  # the generated text's regions
            raise BuildError(
                f"target {f.target}: {f.path!r}: {err}",
                hint=f"this is a fault of target {f.target}: report it",
            ) from None
        if edited and merged.encode("utf-8") != current:
            _save_edited(disk, f.path, current, made, result)
        if lost:
            path = f.path + ".lost"
            try:
                there = disk.read(path)
            except Unreadable as err:
                raise BuildError(
                    f"{disk.output / path} is {err.what}: the regions the model no longer makes "
                    "cannot be added to it",
                    hint="move it away, then build again",
                    exit_code=2,
                ) from None
            data = (there or b"") + lost_text(f.regions, f.path, lost).encode("utf-8")
            result.changes.append(Change(path, "update" if there else "create", there, data))
            result.lost[f.path] = list(lost)
        f = replace(f, data=merged.encode("utf-8"))
    try:
        skeleton = outside(f.regions, f.data.decode("utf-8"))
    except (UnicodeDecodeError, RegionError) as err:
        raise BuildError(
            f"target {f.target}: the protected regions of {f.path!r} are not well formed: {err}",
            hint=f"this is a fault of target {f.target}: report it",
        ) from None
    return f, sha256(skeleton.encode("utf-8"))


def _create(path: Path, data: bytes, executable: bool) -> None:
    """Write a new file at ``path`` (never through a link, never over an existing file)."""
    mode = 0o777 if executable else 0o666  # less the umask, as open() applies it
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, mode)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(descriptor, view) :]
    finally:
        os.close(descriptor)


def _replace(path: Path, data: bytes, executable: bool = False) -> None:
    temporary = path.with_name(f".{path.name}.acordcs-tmp")
    try:
        temporary.unlink(missing_ok=True)  # a leftover keeps its mode; a link is not followed
        _create(temporary, data, executable)
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def apply(output: Path, result: FileChanges) -> None:
    """Carry out ``result`` in ``output`` (created if missing)."""
    if result.fresh:
        _apply_fresh(output, result)
        return
    done: list[str] = []
    made: set[Path] = set()
    try:
        output.mkdir(parents=True, exist_ok=True)
        for change in result.changes:  # what is moved aside unread first: then it is written anew
            if change.action == "move":
                _move(output / change.source, output / change.path)
                done.append(change.path)
        for change in result.changes:
            path = output / change.path
            if change.action == "move":
                continue
            if change.action == "delete":
                path.unlink(missing_ok=True)
                _prune(output, path.parent)
            else:
                if path.parent not in made:
                    path.parent.mkdir(parents=True, exist_ok=True)
                    made.add(path.parent)
                assert change.new is not None
                _replace(path, change.new, change.executable)
            done.append(change.path)
        if result.manifest_changed:
            _replace(output / MANIFEST, result.manifest_bytes)
    except OSError as err:
        where = err.filename or output
        raise BuildError(
            f"{where}: cannot write: {err.strerror}"
            + (f" (already done: {', '.join(done)})" if done else ""),
            hint="check the output directory's permissions and free space, then build again: "
            "the next build finishes the job",
            exit_code=2,
        ) from None


def _move(source: Path, target: Path) -> None:
    """Rename ``source`` (a file a build does not read) to ``target``, which must not exist: a
    hard link then the old name removed (a rename would replace a file that appeared since)."""
    os.link(source, target, follow_symlinks=False)
    source.unlink()


def _apply_fresh(output: Path, result: FileChanges) -> None:
    """Write a new output directory whole, under a temporary name beside it, then rename it: each
    file is created once, in place, and the directory appears complete or not at all."""
    output = Path(os.path.abspath(output))  # a name to rename onto, whatever was given
    staging = output.with_name(f".{output.name}.acordcs-{secrets.token_hex(6)}")
    try:
        if os.path.lexists(output):  # planned without reading it: its files are unknown
            raise FileExistsError(errno.EEXIST, "it exists", str(output))
        output.parent.mkdir(parents=True, exist_ok=True)
        staging.mkdir()  # the mode a new directory gets (0o777 less the umask)
        made = {staging}
        for change in result.changes:
            path = staging / change.path
            if path.parent not in made:
                path.parent.mkdir(parents=True, exist_ok=True)
                made.add(path.parent)
            assert change.new is not None
            _create(path, change.new, change.executable)
        _create(staging / MANIFEST, result.manifest_bytes, False)
        os.rename(staging, output)
    except OSError as err:
        shutil.rmtree(staging, ignore_errors=True)
        appeared = os.path.lexists(output)
        where = str(err.filename or output).replace(str(staging), str(output), 1)
        raise BuildError(
            f"{where}: cannot write: {err.strerror}"
            + (" (the output directory appeared while the build ran)" if appeared else ""),
            hint="check the permissions and free space of the output directory's parent, then "
            "build again; nothing was written",
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
