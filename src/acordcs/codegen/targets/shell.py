"""Target ``shell``: POSIX ``sh`` scripts running the ``python`` target's package, one process per
container.

Files (in ``bin/``): ``env.sh``, sourced by every script (the interpreter, ``PYTHONPATH``, the
run directory, each container's host and port; protected regions for the user's lines, keyed by
the application and by each container's model id, kept by every build:
:mod:`acordcs.codegen.regions`); per container ``<C>-start``, ``<C>-stop`` and ``<C>-status``;
``start-all`` and ``stop-all``.

A Python target rather than a stylesheet: every model string that reaches a script goes through
one function, :func:`quote` (single quotes, ``'`` written ``'\\''``), tested on its own, and the
names are checked with the ``python`` target's own check (the scripts run its modules). Names
(application, containers) are identifiers; anything else from the model (hosts, documentation,
qualified names, ids) is quoted, or only in comments through :func:`acordcs.codegen.headers.comment`
(line breaks and control characters escaped, so it cannot start a line).
"""

from __future__ import annotations

from acordcs.codegen import regions
from acordcs.codegen.headers import comment, header_lines
from acordcs.codegen.registry import target
from acordcs.codegen.targets.names import NameRefused, refused
from acordcs.codegen.targets.python import check_names, package_name

PORT_BASE = 47010
"""The default of ``ACORDCS_PORT_BASE``: container number ``i`` (1, 2, ... in model order) serves
at ``ACORDCS_PORT_BASE + i`` unless the model gives it a port (tag ``port``) or its
``ACORDCS_<C>_PORT`` is set."""


def quote(text: str) -> str:
    """``text`` as one ``sh`` word that is exactly ``text``: in single quotes, each ``'`` written
    ``'\\''``. NUL cannot be in a shell word: refused (ValueError)."""
    if "\0" in text:
        raise ValueError("a NUL character cannot be written into a shell script")
    return "'" + text.replace("'", "'\\''") + "'"


def needs(app, container: str) -> list[str]:
    """The other containers ``container`` must be given with ``--remote`` (as
    :func:`acordcs.runtime.assembly.assemble` requires them): the containers across a connection
    it calls (required end here), or that calls one of its ports that is not synchronous, and the
    containers of the policy sets its monitors feed."""
    where = {r.name: c.name for c in app.containers for r in c.hosts}
    found: set[str] = set()
    for conn in app.connections:
        caller = where.get(conn.required.component)
        callee = where.get(conn.provided.component)
        if caller is None or callee is None or caller == callee:
            continue
        if caller == container:
            found.add(callee)
        elif callee == container:
            comp = next((c for c in app.components if c.name == conn.provided.component), None)
            port = comp.port(conn.provided.port) if comp is not None else None
            if port is None or port.kind != "synchronous":
                found.add(caller)
    for mon in app.monitors:
        if where.get(mon.name) != container:
            continue
        for fed in mon.feeds:
            other = where.get(fed.name)
            if other is not None and other != container:
                found.add(other)
    return [c.name for c in app.containers if c.name in found]


def _header(context, what: str, note: str = "") -> str:
    return "#!/bin/sh\n" + comment(
        "hash", header_lines(context.target, what, context.source_name, note)
    )


def _what(c) -> str:
    return f"container '{c.name}' ({c.qualified_name}, id {c.id})"


_RESOLVE = """\
bin=$(CDPATH='' cd -- "$(dirname -- "$0")" && pwd) || exit 1
# shellcheck source=env.sh
. "$bin/env.sh"
"""

_ALIVE = """\
# alive PID: whether process PID runs (a zombie does not).
alive() {
    kill -0 "$1" 2>/dev/null || return 1
    case $(ps -o stat= -p "$1" 2>/dev/null) in Z*) return 1 ;; esac
    return 0
}
"""


def env_file(context, app) -> str:
    pkg = package_name(app.name)
    out = [
        _header(
            context,
            f"application '{app.name}'",
            "Sourced by the scripts of this directory. Your lines go between BEGIN USER and END "
            "USER: kept by every build.",
        ).removeprefix("#!/bin/sh\n"),
        "# A variable already set in the environment wins over the defaults below\n",
        "# (ACORDCS_PORT_BASE=48000 bin/start-all); set one in a region to change its default.\n",
        "# shellcheck disable=SC2034,SC2154  # used by the scripts sourcing it, which set $bin\n",
        "\n",
        regions.begin("hash", "application") + "\n",
        regions.end("hash", "application") + "\n",
        "\n",
        '[ -n "${PYTHON-}" ] || PYTHON=python3\n',
        "# The directory holding the package " + pkg + "/ (this file's parent directory).\n",
        "ACORDCS_HOME=$(CDPATH='' cd -- \"$bin/..\" && pwd) || exit 1\n",
        "PYTHONPATH=$ACORDCS_HOME${PYTHONPATH:+:$PYTHONPATH}\n",
        "export PYTHONPATH\n",
        f"ACORDCS_PACKAGE={pkg}\n",
        '[ -n "${ACORDCS_RUN_DIR-}" ] || ACORDCS_RUN_DIR=./run\n',
        "# The application's token: each of its processes presents it to the others "
        "(ACORDCS_TOKEN\n# wins; else the one in $ACORDCS_RUN_DIR/token, made once from "
        "128 random bits).\n",
        'if [ -z "${ACORDCS_TOKEN-}" ]; then\n',
        '    if [ ! -s "$ACORDCS_RUN_DIR/token" ]; then\n',
        '        (umask 077 && mkdir -p -- "$ACORDCS_RUN_DIR" &&\n',
        "            od -An -tx1 -N16 /dev/urandom | tr -d ' \\n' >\"$ACORDCS_RUN_DIR/token\") "
        "|| exit 1\n",
        "    fi\n",
        '    ACORDCS_TOKEN=$(cat -- "$ACORDCS_RUN_DIR/token") || exit 1\n',
        "fi\n",
        "export ACORDCS_TOKEN\n",
        "# python -m " + pkg + ".<Container> options: --clock virtual|real, --duration "
        "SECONDS (empty: until stopped), --timeout SECONDS\n",
        '[ -n "${ACORDCS_CLOCK-}" ] || ACORDCS_CLOCK=real\n',
        "ACORDCS_DURATION=${ACORDCS_DURATION-}\n",
        '[ -n "${ACORDCS_TIMEOUT-}" ] || ACORDCS_TIMEOUT=5\n',
        "# Seconds a stop waits after TERM before KILL.\n",
        '[ -n "${ACORDCS_STOP_TIMEOUT-}" ] || ACORDCS_STOP_TIMEOUT=10\n',
        f'[ -n "${{ACORDCS_PORT_BASE-}}" ] || ACORDCS_PORT_BASE={PORT_BASE}\n',
    ]
    for n, c in enumerate(app.containers, 1):
        key = regions.key(c.id)
        out += [
            "\n",
            comment("hash", [f"Container {c.name} ({c.qualified_name}, id {c.id})"]),
            regions.begin("hash", key) + "\n",
            regions.end("hash", key) + "\n",
            f'[ -n "${{ACORDCS_{c.name}_HOST-}}" ] || ACORDCS_{c.name}_HOST='
            f"{quote(c.host or 'localhost')}\n",
            f'[ -n "${{ACORDCS_{c.name}_PORT-}}" ] || '
            + (
                f"ACORDCS_{c.name}_PORT={c.endpoint.port}  # the model's tag port\n"
                if c.endpoint is not None and c.endpoint.port is not None
                else f"ACORDCS_{c.name}_PORT=$((ACORDCS_PORT_BASE + {n}))\n"
            ),
            "# Operations to call once it serves, COMPONENT.OPERATION blank-separated (--run).\n",
            f"ACORDCS_{c.name}_RUN=${{ACORDCS_{c.name}_RUN-}}\n",
        ]
    return "".join(out)


def start_script(context, app, c) -> str:
    pkg = package_name(app.name)
    remote = []
    for other in needs(app, c.name):
        o = next(x for x in app.containers if x.name == other)
        obj = o.endpoint.object_name if o.endpoint is not None else f"acordcs.container.{o.name}"
        remote.append(
            f'    --remote {quote(f"{o.name}=PYRO:{obj}@")}"$ACORDCS_{o.name}_HOST:'
            f'$ACORDCS_{o.name}_PORT" \\\n'
        )
    return (
        _header(
            context,
            _what(c),
            f"Starts it in the background: python -m {pkg}.{c.name}, its pid in "
            f"$ACORDCS_RUN_DIR/{c.name}.pid, its output in $ACORDCS_RUN_DIR/{c.name}.log. "
            "Arguments are added to the module's options. Exit: 0 started, 1 it stopped at "
            "once (the log's end is shown), 2 already running.",
        )
        + "set -u\n"
        + _RESOLVE
        + _ALIVE
        + f"pidfile=$ACORDCS_RUN_DIR/{c.name}.pid\n"
        + f"logfile=$ACORDCS_RUN_DIR/{c.name}.log\n"
        + 'mkdir -p -- "$ACORDCS_RUN_DIR" || exit 1\n'
        + 'if [ -f "$pidfile" ]; then\n'
        + '    pid=$(cat -- "$pidfile")\n'
        + '    if [ -n "$pid" ] && alive "$pid"; then\n'
        + f'        echo "{c.name}: already running (pid $pid, $pidfile): not started; '
        + f'stop it first with $bin/{c.name}-stop" >&2\n'
        + "        exit 2\n"
        + "    fi\n"
        + '    rm -f -- "$pidfile"\n'
        + "fi\n"
        + f'set -- --clock "$ACORDCS_CLOCK" --serve "$ACORDCS_{c.name}_PORT" '
        + f'--host "$ACORDCS_{c.name}_HOST" \\\n'
        + "".join(remote)
        + '    --timeout "$ACORDCS_TIMEOUT" "$@"\n'
        + 'if [ -n "$ACORDCS_DURATION" ]; then set -- --duration "$ACORDCS_DURATION" "$@"; fi\n'
        + f"# ACORDCS_{c.name}_RUN: operations to call once it serves (--run), blank-separated.\n"
        + f'for op in ${{ACORDCS_{c.name}_RUN-}}; do set -- "$@" --run "$op"; done\n'
        + f'nohup "$PYTHON" -m "$ACORDCS_PACKAGE.{c.name}" "$@" >>"$logfile" 2>&1 </dev/null &\n'
        + "pid=$!\n"
        + 'echo "$pid" >"$pidfile"\n'
        + "sleep 1\n"
        + 'if ! alive "$pid"; then\n'
        + '    rm -f -- "$pidfile"\n'
        + f'    echo "{c.name}: stopped at once; the end of $logfile:" >&2\n'
        + '    tail -n 20 -- "$logfile" >&2\n'
        + "    exit 1\n"
        + "fi\n"
        + f'echo "{c.name}: started (pid $pid, log $logfile)"\n'
    )


def stop_script(context, app, c) -> str:
    return (
        _header(
            context,
            _what(c),
            "Stops it: TERM, then KILL after $ACORDCS_STOP_TIMEOUT seconds; removes its pid "
            "file. Exit 0 (also when it was not running).",
        )
        + "set -u\n"
        + _RESOLVE
        + _ALIVE
        + f"pidfile=$ACORDCS_RUN_DIR/{c.name}.pid\n"
        + 'pid=$(cat -- "$pidfile" 2>/dev/null) || pid=\n'
        + 'if [ -z "$pid" ] || ! alive "$pid"; then\n'
        + '    rm -f -- "$pidfile"\n'
        + f'    echo "{c.name}: not running"\n'
        + "    exit 0\n"
        + "fi\n"
        + 'kill -TERM "$pid" 2>/dev/null\n'
        + "waited=0\n"
        + 'while alive "$pid"; do\n'
        + '    if [ "$waited" -ge "$ACORDCS_STOP_TIMEOUT" ]; then\n'
        + '        kill -KILL "$pid" 2>/dev/null\n'
        + f'        echo "{c.name}: killed (pid $pid): it did not stop within '
        + '$ACORDCS_STOP_TIMEOUT s of TERM"\n'
        + "        break\n"
        + "    fi\n"
        + "    sleep 1\n"
        + "    waited=$((waited + 1))\n"
        + "done\n"
        + 'rm -f -- "$pidfile"\n'
        + f'echo "{c.name}: stopped (pid $pid)"\n'
    )


def status_script(context, app, c) -> str:
    return (
        _header(
            context,
            _what(c),
            "Says whether it runs. Exit (LSB): 0 running, 3 not running.",
        )
        + "set -u\n"
        + _RESOLVE
        + _ALIVE
        + f"pidfile=$ACORDCS_RUN_DIR/{c.name}.pid\n"
        + 'pid=$(cat -- "$pidfile" 2>/dev/null) || pid=\n'
        + 'if [ -n "$pid" ] && alive "$pid"; then\n'
        + f'    echo "{c.name}: running (pid $pid)"\n'
        + "    exit 0\n"
        + "fi\n"
        + f'echo "{c.name}: not running"\n'
        + "exit 3\n"
    )


def all_script(context, app, verb: str) -> str:
    order = list(app.containers) if verb == "start" else list(reversed(app.containers))
    note = (
        "Starts every container (arguments go to each). Exit 0 when all started."
        if verb == "start"
        else "Stops every container. Exit 0."
    )
    args = ' "$@"' if verb == "start" else ""
    return (
        _header(context, f"application '{app.name}'", note)
        + "set -u\n"
        + 'bin=$(CDPATH=\'\' cd -- "$(dirname -- "$0")" && pwd) || exit 1\n'
        + "status=0\n"
        + "".join(f'sh "$bin/{c.name}-{verb}"{args} || status=1\n' for c in order)
        + "exit $status\n"
    )


@target(
    "shell",
    description="POSIX sh scripts starting, stopping and checking each container of the python "
    "package, and an environment file with protected regions",
)
def shell(context) -> None:
    """POSIX sh scripts per container (start, stop, status), start-all, stop-all, env.sh."""
    app = context.application
    try:
        check_names(app)
    except NameRefused as err:
        raise refused(context, err, "shell") from None
    ids = tuple(c.id for c in app.containers)
    context.emit("bin/env.sh", env_file(context, app), element=app.name, ids=ids, regions="hash")
    for c in app.containers:
        for verb, make in (
            ("start", start_script),
            ("stop", stop_script),
            ("status", status_script),
        ):
            context.emit(
                f"bin/{c.name}-{verb}",
                make(context, app, c),
                element=c.qualified_name,
                ids=(c.id,),
                executable=True,
            )
    for verb in ("start", "stop"):
        context.emit(
            f"bin/{verb}-all",
            all_script(context, app, verb),
            element=app.name,
            ids=ids,
            executable=True,
        )


__all__ = ["PORT_BASE", "needs", "quote", "shell"]
