"""Where a built application's containers serve, found as its generated scripts find them.

The scripts of the ``shell`` target (``bin/``) take their settings from ``bin/env.sh``: the run
directory, the application's token, each container's host and port, each with its default and
the environment winning over it. Rather than restating those rules, :func:`settings` sources
``env.sh`` in ``sh`` as the scripts do (same environment, same working directory) and reads back
what it set: what ``acordcs-gen update`` (:mod:`acordcs.cli.running`) and a console
(:mod:`acordcs.console.attaching`) reach.
"""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from acordcs.bounded_read import read_bounded
from acordcs.descriptor import DescriptorError, from_xml
from acordcs.errors import AcordError

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")

# Sourced as a script of bin/ sources it ($bin set), then each value NUL-terminated (a value may
# hold any other character). "$@": the containers whose host and port are wanted.
_READ = r"""
bin=$1
shift
. "$bin/env.sh" || exit 2
printf '%s\0' "$ACORDCS_RUN_DIR" "${ACORDCS_TOKEN-}" "$ACORDCS_PACKAGE"
for c; do
    eval "printf '%s\0%s\0' \"\${ACORDCS_${c}_HOST-}\" \"\${ACORDCS_${c}_PORT-}\""
done
"""


class NotFound(AcordError):
    """No application to update in the directory, or its scripts refuse their settings."""

    exit_code = 2


@dataclass(frozen=True)
class Settings:
    """What ``bin/env.sh`` sets: the run directory, the token, the package, and each container's
    host and port (``containers``: name -> (host, port))."""

    run_dir: str
    token: str
    package: str
    containers: dict[str, tuple[str, str]] = field(default_factory=dict)


def _source(app: Path, names: list[str], timeout: float) -> list[str]:
    env_sh = app / "bin" / "env.sh"
    if not env_sh.is_file():
        raise NotFound(
            f"{app} has no bin/env.sh: not an application built by acordcs-gen build (the "
            "shell target writes it), so no container of it can be found",
            hint="build it (acordcs-gen build MODEL -o DIR), start it (DIR/bin/start-all), then "
            "update it",
        )
    try:
        done = subprocess.run(
            ["sh", "-c", _READ, "acordcs-gen update", str(env_sh.parent.resolve()), *names],
            capture_output=True,
            timeout=timeout,
            check=False,
        )
    except (OSError, subprocess.TimeoutExpired) as err:
        raise NotFound(f"{env_sh}: cannot source it in sh: {err}") from None
    if done.returncode != 0:
        said = done.stderr.decode("utf-8", "replace").strip() or f"exit {done.returncode}"
        raise NotFound(
            f"{env_sh} refused its settings: {said}",
            hint="fix what it says, as its scripts would need it to start the application",
        )
    values = done.stdout.decode("utf-8", "surrogateescape").split("\0")
    if len(values) < 3 + 2 * len(names):
        raise NotFound(f"{env_sh}: sourcing it printed something else than its settings")
    return values


def settings(app: Path, *, timeout: float = 10.0) -> Settings:
    """What ``app/bin/env.sh`` sets, sourced in ``sh`` (see the module docstring), for the
    containers of the descriptor the application directory holds (what its scripts start)."""
    run_dir, token, package = _source(app, [], timeout)[:3]
    if not _IDENTIFIER.match(package):
        raise NotFound(f"{app / 'bin' / 'env.sh'}: ACORDCS_PACKAGE is {package!r}, not a package")
    path = app / package / "descriptor.xml"
    try:
        data = read_bounded(path)  # a FIFO or a huge file: refused at once, never waited on
        names = [c.name for c in from_xml(data, file=str(path)).containers]
    except (OSError, DescriptorError) as err:
        raise NotFound(
            f"{path}: cannot read the descriptor the application was built with: {err}",
            hint="build the application (acordcs-gen build) and start it first",
        ) from None
    names = [n for n in names if _IDENTIFIER.match(n)]  # the scripts' names are identifiers
    values = _source(app, names, timeout)
    hosts = {n: (values[3 + 2 * i], values[4 + 2 * i]) for i, n in enumerate(names)}
    return Settings(run_dir, token, package, hosts)
