"""``python -m acordcs.profile``: regenerate the shipped profile files from the declaration.

Writes ``ACORDCS.xmi`` (BOUML) and ``ACORDCS.profile.uml`` (Papyrus) next to the package, and
only those whose content changed, so an unchanged declaration leaves the tree untouched.
"""

from __future__ import annotations

import sys

from acordcs.profile.profile_files import OUTPUTS, default_directory, write_profiles


def main() -> int:
    written = write_profiles()
    for path in written:
        print(f"wrote {path}")
    for name in sorted(set(OUTPUTS) - {p.name for p in written}):
        print(f"up to date {default_directory() / name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
