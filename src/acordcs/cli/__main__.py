"""``python -m acordcs.cli ARGS``: ``acordcs-gen ARGS`` with this interpreter (what a generated
application's ``bin/console`` runs: ``python -m acordcs.cli console APPDIR``)."""

from __future__ import annotations

import sys

from acordcs.cli import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
