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
from pathlib import Path

from acordcs.codegen.headers import GENERATOR
from acordcs.codegen.paths import MANIFEST, path_problem

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
        data = {
            "format": FORMAT,
            "generator": GENERATOR,
            "model": {"file": self.model, "sha256": self.model_sha256},
            "targets": {name: dict(sorted(t.items())) for name, t in sorted(self.targets.items())},
            "files": {
                path: {
                    "sha256": e.sha256,
                    "target": e.target,
                    "element": e.element,
                    "ids": list(e.ids),
                    **({"user": True} if e.user else {}),
                    **({"outside_sha256": e.outside} if e.outside else {}),
                }
                for path, e in sorted(self.files.items())
            },
        }
        return (json.dumps(data, indent=1, sort_keys=True, ensure_ascii=False) + "\n").encode()


class ManifestError(Exception):
    """The manifest exists but cannot be used (what is wrong, in words)."""


def read_manifest(output: Path) -> Manifest | None:
    """The manifest of ``output``, None when there is none; ManifestError when it is unreadable
    or not ours (an entry whose path could leave the directory is refused, not trusted)."""
    path = output / MANIFEST
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        return None
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
