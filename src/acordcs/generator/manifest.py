"""The build's record in the output directory: ``.acordcs-manifest.json``.

It lists every file the builds wrote there, with its sha256, the target that made it, the model
element it comes from and the ids of the model elements it holds (traceability), and, per target,
the fingerprint of its code and the sha256 of the model it was last built from. A file with
protected regions also has the sha256 of its lines outside them (``outside_sha256``). A build
deletes a file only when the manifest lists it (never a user's file: one recorded as ``user``, or
whose header says so), and does nothing at all when the model and the targets' code are those of
the manifest and every listed file is intact. The manifest says which files are generated, never
what they hold: ``build --check`` compares the bytes a build makes with the files on disk.

Written with sorted keys and without a date: the same build writes the same bytes.
"""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import dataclass, field
from json.encoder import encode_basestring  # type: ignore[attr-defined]  # C, ensure_ascii=False
from pathlib import Path

from acordcs.generator.headers import GENERATOR
from acordcs.generator.paths import MANIFEST, Unreadable, path_problem, read_bounded

FORMAT = 1
_SHA256 = re.compile(r"[0-9a-f]{64}")


@dataclass(frozen=True)
class Entry:
    sha256: str
    target: str
    element: str = ""
    ids: tuple[str, ...] = ()
    user: bool = False  # written once, then the user's: never overwritten, never deleted
    outside: str = ""  # a file with protected regions: sha256 of its lines outside them


@dataclass
class Manifest:
    model: str = ""  # the model file's base name
    model_sha256: str = ""
    targets: dict[str, dict[str, str]] = field(default_factory=dict)  # fingerprint, model_sha256
    files: dict[str, Entry] = field(default_factory=dict)

    def to_bytes(self) -> bytes:
        """The manifest's JSON: ``json.dumps(..., indent=1, sort_keys=True, ensure_ascii=False)``
        of its data, character for character, written here: the json module encodes with an
        indent in pure Python, several times slower on a 2,400-file manifest."""
        head = {
            "format": FORMAT,
            "generator": GENERATOR,
            "model": {"file": self.model, "sha256": self.model_sha256},
            "targets": {name: dict(t) for name, t in self.targets.items()},
        }
        files = ",\n".join(_entry(path, e) for path, e in sorted(self.files.items()))
        items = [f' "files": {{\n{files}\n }}' if files else ' "files": {}']
        items += [f" {_json(key)}: {_indented(head[key], chr(10) + ' ')}" for key in sorted(head)]
        return ("{\n" + ",\n".join(items) + "\n}\n").encode()


def _json(value: object) -> str:
    """A string or int (all the head holds) as JSON (strings not escaped beyond what JSON needs)."""
    if isinstance(value, str):
        return encode_basestring(value)
    return str(int(value))  # type: ignore[call-overload]


def _indented(value: object, newline: str) -> str:
    """``value`` (the head's dicts of strings and ints) as ``json.dumps(value, indent=1,
    sort_keys=True, ensure_ascii=False)`` writes it at the indentation ``newline`` ends with."""
    if isinstance(value, dict):
        if not value:
            return "{}"
        inner = newline + " "
        items = (f"{_json(key)}: {_indented(value[key], inner)}" for key in sorted(value))
        return "{" + inner + ("," + inner).join(items) + newline + "}"
    return _json(value)


def _entry(path: str, e: Entry) -> str:
    """One file's entry, as :func:`_indented` writes it inside ``"files"`` (keys sorted)."""
    ids = ("[\n    " + ",\n    ".join(map(encode_basestring, e.ids)) + "\n   ]") if e.ids else "[]"
    fields = [f'   "element": {encode_basestring(e.element)}', f'   "ids": {ids}']
    if e.outside:
        fields.append(f'   "outside_sha256": {encode_basestring(e.outside)}')
    fields.append(f'   "sha256": {encode_basestring(e.sha256)}')
    fields.append(f'   "target": {encode_basestring(e.target)}')
    if e.user:
        fields.append('   "user": true')
    return f"  {encode_basestring(path)}: {{\n" + ",\n".join(fields) + "\n  }"


class ManifestError(Exception):
    """The manifest exists but cannot be used (what is wrong, in words)."""


def read_manifest(output: Path) -> Manifest | None:
    """The manifest of ``output``, None when there is none; ManifestError when it is unreadable
    or not ours (an entry whose path could leave the directory is refused, not trusted)."""
    path = output / MANIFEST
    try:
        raw = read_bounded(path)  # a FIFO or a huge file: refused at once, never waited on
    except FileNotFoundError:
        return None
    except Unreadable as err:
        raise ManifestError(f"it is {err.what}, not read") from None
    except OSError as err:
        raise ManifestError(f"cannot read it: {err.strerror}") from None
    try:
        data = json.loads(raw)
        if data.get("format") != FORMAT:
            raise ManifestError(f"format {data.get('format')!r}, not {FORMAT}")
        files = {}
        for rel, e in data["files"].items():
            problem = path_problem(rel)
            if problem:
                raise ManifestError(f"it lists {rel!r}: {problem}")
            for key in ("sha256", "outside_sha256"):
                if key in e and not _SHA256.fullmatch(str(e[key])):
                    raise ManifestError(f"the {key} of {rel!r} is not a sha256")
            files[rel] = Entry(
                str(e["sha256"]),
                str(e["target"]),
                str(e.get("element", "")),
                tuple(map(str, e.get("ids", ()))),
                e.get("user", False) is True,
                str(e.get("outside_sha256", "")),
            )
        targets = {
            str(k): {str(a): str(b) for a, b in v.items()} for k, v in data["targets"].items()
        }
        model = data.get("model", {})
        return Manifest(str(model.get("file", "")), str(model.get("sha256", "")), targets, files)
    except ManifestError:
        raise
    except (ValueError, KeyError, TypeError, AttributeError) as err:
        raise ManifestError(f"it is not a manifest this version writes ({err})") from None


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()
