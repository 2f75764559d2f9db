"""Import a downloaded factory package once in a child process, with a deadline, before it is
imported into this one.

A package whose hash matched its description is trusted code (see docs/providers.md, "Security
model: the component provider"), but a broken one must not take the installing process down: an
import that calls ``sys.exit``, never returns, or changes the process (patching ``hashlib``, say)
and then fails does so in the child, and the install is refused before any of its code runs here.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

OK = "ACORDCS-VETTED"
FAILED = "ACORDCS-FAILED"

_CHILD = f"""
import importlib, importlib.util, os, sys
directory, entry = sys.argv[1], sys.argv[2]
module_path, attribute = entry.split(":")
top, _, rest = module_path.partition(".")
alias = "_acordcs_vetting"
package = directory + "/" + top
if os.path.isfile(package + "/__init__.py"):
    spec = importlib.util.spec_from_file_location(
        alias, package + "/__init__.py", submodule_search_locations=[package]
    )
else:
    spec = importlib.util.spec_from_file_location(alias, directory + "/" + top + ".py")
module = importlib.util.module_from_spec(spec)
sys.modules[alias] = module
try:
    spec.loader.exec_module(module)
    if rest:
        module = importlib.import_module(alias + "." + rest)
    getattr(module, attribute)
except Exception as err:
    print({FAILED!r}, type(err).__name__ + ":", err, flush=True)
    sys.exit(1)
print({OK!r}, flush=True)
"""


def vet_import(directory: Path, entry: str, deadline: float) -> str | None:
    """None when importing ``entry`` from ``directory`` in a child process finishes within
    ``deadline`` seconds; else what went wrong, in a phrase."""
    env = dict(os.environ)
    # the child sees what this process imports from (acordcs itself, for component classes)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if isinstance(p, str) and p)
    try:
        done = subprocess.run(
            [sys.executable, "-c", _CHILD, str(directory), entry],
            capture_output=True,
            text=True,
            timeout=deadline,
            env=env,
            cwd=directory,
            stdin=subprocess.DEVNULL,
        )
    except subprocess.TimeoutExpired:
        return f"importing it did not finish within {deadline:g} s"
    last = (done.stdout.strip().splitlines() or [""])[-1]
    if done.returncode == 0 and last == OK:
        return None
    if last.startswith(FAILED + " "):
        return f"importing entry {entry!r} failed: {last.removeprefix(FAILED + ' ')}"
    if done.returncode == 0:
        return f"importing entry {entry!r} ended the process (sys.exit at import?)"
    error = (done.stderr.strip().splitlines() or ["no message"])[-1]
    return f"importing entry {entry!r} ended the process with exit {done.returncode}: {error}"
