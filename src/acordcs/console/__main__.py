"""``python -m acordcs.console APPDIR [OPTIONS]``: ``acordcs-gen console`` (what a generated
application's ``bin/console`` runs, with the interpreter its scripts run)."""

from __future__ import annotations

import sys

from acordcs.cli import main

if __name__ == "__main__":
    sys.exit(main(["console", *sys.argv[1:]]))
