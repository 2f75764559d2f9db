"""The ACORDCS profile as files a modeller imports, produced from the one declaration.

Two dialects, both from :func:`acordcs.profile.declaration.profile`:

* :func:`bouml_xmi` (:mod:`acordcs.profile.bouml`) -- BOUML's XMI 2.1, as BOUML's own exporter
  writes an in-model profile, so that its XMI 2.1 import plug-out reads it back as a profile;
* :func:`eclipse_profile` (:mod:`acordcs.profile.papyrus`) -- an Eclipse UML2 ``.profile.uml``
  for Papyrus, shaped like a real Papyrus-made profile.

Both check the declaration first (:mod:`acordcs.profile.writing`).

Ids are derived from names, never random or counted per run, so the output is byte-identical for
the same declaration and a model that applied an earlier version of the profile keeps resolving.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path

from acordcs.profile.bouml import bouml_xmi
from acordcs.profile.papyrus import eclipse_profile
from acordcs.profile.writing import ProfileExportError

__all__ = [
    "OUTPUTS",
    "ProfileExportError",
    "bouml_xmi",
    "default_directory",
    "eclipse_profile",
    "write_profiles",
]

BOUML_FILE = "ACORDCS.xmi"
ECLIPSE_FILE = "ACORDCS.profile.uml"

# --- files ---------------------------------------------------------------------------------------

OUTPUTS: dict[str, Callable[[], bytes]] = {BOUML_FILE: bouml_xmi, ECLIPSE_FILE: eclipse_profile}


def default_directory() -> Path:
    """Where the shipped profile files live (next to this module)."""
    return Path(__file__).resolve().parent


def write_profiles(
    directory: Path | str | None = None, names: Iterable[str] | None = None
) -> list[Path]:
    """Write the profile files ``names`` (default both, see :data:`OUTPUTS`) into ``directory``
    (default: the package); only files whose content changed are rewritten. Returns the paths
    written."""
    target = default_directory() if directory is None else Path(directory)
    if not target.is_dir():
        raise NotADirectoryError(
            f"cannot write the ACORDCS profile files: {target} is not a directory; create it or "
            "pass an existing one"
        )
    written = []
    wanted = set(OUTPUTS if names is None else names)
    for name, produce in OUTPUTS.items():
        if name not in wanted:
            continue
        path = target / name
        data = produce()
        try:
            current = path.read_bytes()
        except FileNotFoundError:
            current = None
        if current != data:
            tmp = path.with_suffix(path.suffix + ".tmp")
            tmp.write_bytes(data)
            tmp.replace(path)
            written.append(path)
    return written
