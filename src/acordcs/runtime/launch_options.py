"""The command line of a generated container's process (``python -m <package>.<Container>``):
its options, how each is read and checked, and the exit statuses its ``--help`` lists. The
:class:`~acordcs.runtime.launcher.Launcher` runs what they say."""

from __future__ import annotations

import argparse
import os
from collections.abc import Sequence
from pathlib import Path

from acordcs.runtime.broker_setting import (
    CA_ENV,
    CONTEXT_ENV,
    PASSWORD_ENV,
    BrokerSetting,
    parse_context,
)
from acordcs.runtime.run_arguments import RunCall, RunError, parse_run

EXIT_OK = 0
EXIT_RUN_FAILED = 1
EXIT_NOT_STARTED = 2
EXIT_FAULTS = 3

EXIT_STATUS = f"""exit status:
  {EXIT_OK}  stopped with no fault recorded (or with faults, given --faults-ok)
  {EXIT_RUN_FAILED}  a --run operation failed
  {EXIT_NOT_STARTED}  not started: a usage error (a --run whose arguments do not fit), a
     descriptor that cannot be read or fails its schema, classes that do not
     import, an assembly failure, an operation without code under --strict, a
     port that cannot be served, a --context broker not reached
  {EXIT_FAULTS}  stopped after recording faults (the last line says how many)"""


def container_parser(prog: str, package: str, container: str) -> argparse.ArgumentParser:
    """The command line of container ``container`` of the application in ``package``."""
    parser = argparse.ArgumentParser(
        prog=prog,
        description=f"Run container {container} of the application in package "
        f"{package} (its descriptor.xml).",
        epilog="ACORDCS_TOKEN: the application's token, the same in each of its processes; "
        "--serve admits only callers presenting it, --remote presents it (required to serve "
        "a host other than loopback).\n\n" + EXIT_STATUS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add = parser.add_argument
    add("--clock", choices=("virtual", "real"), default="virtual",
        help="virtual: simulated time, as fast as it runs (default); real: wall time")  # fmt: skip
    add("--seed", type=int, default=0, help="the virtual clock's seed (default 0)")
    add("--duration", type=float, metavar="SECONDS",
        help="how long to run (default: 10 virtual seconds; real: until interrupted)")  # fmt: skip
    add("--serve", type=int, metavar="PORT",
        help="serve the container to other processes at this TCP port (0: any)")  # fmt: skip
    add("--host", help="the host to serve at (default: the container's host in the model)")
    add("--remote", type=remote_option, action="append", default=[], metavar="NAME=URI",
        help="the URI of another container (repeat for each)")  # fmt: skip
    add("--timeout", type=float, default=5.0, help="remote call timeout, s")
    add("--context", type=context_option, default=os.environ.get(CONTEXT_ENV, ""),
        metavar="embedded|mqtt[s]://[USER@]HOST[:PORT][/PREFIX]",
        help="where the context documents go: in this process (embedded, the default) or "
        f"through an MQTT broker other containers share (default: ${CONTEXT_ENV}; the "
        f"password in ${PASSWORD_ENV}; mqtts: TLS, the broker's CA in ${CA_ENV}); a broker "
        "not reached within --timeout: exit 2")  # fmt: skip
    add("--run", type=run_option, action="append", default=[], metavar="COMPONENT.OPERATION",
        help="call this operation of a component hosted here once the container serves, in "
        "a worker thread (virtual clock: in turn, before the duration runs); its failure "
        "stops the container, exit 1 (repeat for each). Arguments in parentheses, typed by "
        "the model's parameters: numbers, true or false, strings in quotes, by position or "
        "name: 'Display.watch(5)', \"Display.show('a b', size=2.5)\"; a value that does not "
        "fit its parameter is exit 2, before anything starts")  # fmt: skip
    add("--strict", action="store_true",
        help="do not start (exit 2) when an operation that the model calls has no code (the "
        "warnings at start list them)")  # fmt: skip
    add("--faults-ok", action="store_true",
        help="exit 0, not 3, when faults were recorded (experiments that expect some)")  # fmt: skip
    add("--updates-without-token", action="store_true",
        help="served on a loopback host without ACORDCS_TOKEN: take updates (acordcs-gen "
        "update) all the same; any local process could then change it")  # fmt: skip
    add("--console", type=int, metavar="PORT",
        help="serve the browser console of this container on 127.0.0.1:PORT (0: any; "
        "needs --clock real; serves the container on loopback if --serve is not given); "
        "its link is printed")  # fmt: skip
    add("--state-dir", type=state_dir_option, metavar="DIR",
        help="keep the state of the components the model tags persistent in DIR (the "
        "run directory, as bin/<Container>-start gives it): restored at start, written as "
        "it changes and at stop; not given: their state is not kept")  # fmt: skip
    add("--exit-file", type=exit_file_option, metavar="PATH",
        help="at exit, write 'EXIT_CODE FAULTS' (one line, mode 0600) to PATH, replacing it "
        "at once; an existing one is removed at start")  # fmt: skip
    return parser


def console_options(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """``--console``: a port, a real clock, and the container served (on loopback unless
    ``--serve`` and ``--host`` say otherwise)."""
    if args.console is None:
        return
    if not 0 <= args.console <= 65535:
        parser.error(f"--console {args.console}: a TCP port is 0 to 65535")
    if args.clock != "real":
        parser.error("--console needs --clock real (on the virtual clock the run is over at once)")
    if args.serve is None:
        args.serve, args.host = 0, args.host or "127.0.0.1"


def remote_option(text: str) -> tuple[str, str]:
    name, sep, uri = text.partition("=")
    if not sep or not name or not uri:
        raise argparse.ArgumentTypeError(f"{text!r} is not NAME=URI")
    return name, uri


def context_option(text: str) -> BrokerSetting | None:
    try:
        return parse_context(text)
    except ValueError as err:
        given = " (the setting $" + CONTEXT_ENV + ")" if text == os.environ.get(CONTEXT_ENV) else ""
        raise argparse.ArgumentTypeError(f"{err}{given}") from None


def run_option(text: str) -> RunCall:
    try:
        return parse_run(text)
    except RunError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def exit_file_option(text: str) -> Path:
    path = Path(text)
    if not text or path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a directory, not a file to write")
    if not path.parent.is_dir():
        raise argparse.ArgumentTypeError(
            f"{text!r}: its directory {str(path.parent)!r} does not exist (create it first)"
        )
    return path


def state_dir_option(text: str) -> Path:
    path = Path(text)
    if not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is not a directory (create it first)")
    return path


def exit_file_given(argv: Sequence[str]) -> Path | None:
    """The --exit-file of a command line argparse refused, if it names a file one can write."""
    for i, arg in enumerate(argv):
        text = argv[i + 1] if arg == "--exit-file" and i + 1 < len(argv) else None
        if arg.startswith("--exit-file="):
            text = arg.partition("=")[2]
        if text is not None:
            try:
                return exit_file_option(text)
            except argparse.ArgumentTypeError:
                return None
    return None
