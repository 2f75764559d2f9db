"""Running one container of a generated application: ``python -m <package>.<Container>``.

A container module of the ``python`` target names its package and container and hands over to a
:class:`Launcher`, which owns the rest: the command line, the clock, the container assembled from
the package's ``descriptor.xml`` with the package's classes (``<package>.registry``), the
operations without code that the model calls (:mod:`acordcs.runtime.live.code_check`), serving, ``--run``,
signals and the exit status::

    LAUNCHER = Launcher("weblab_app", "UserSide")
    assemble_container = LAUNCHER.assemble
    if __name__ == "__main__":
        sys.exit(LAUNCHER.main())

``--run`` calls are read and typed by the model before anything starts
(:mod:`acordcs.runtime.run_arguments`). Served on a real clock, the container says it serves (the
line its start script waits for) at the end of its start-up: once its ``--run`` calls have
returned or run for :data:`RUN_START_WINDOW` seconds; one failing in that time stops it first.

Exit status (:data:`~acordcs.runtime.launch_options.EXIT_STATUS`, also in ``--help`` and
docs/build.md; the options: :mod:`~acordcs.runtime.launch_options`): 0 stopped without fault
(or with faults and ``--faults-ok``); 1 a ``--run`` operation failed; 2 not started (a usage
error, a ``--run`` whose arguments do not fit, a descriptor that cannot be read or fails its
schema, component or monitor classes that do not import, an assembly failure, an operation without
code under ``--strict``, a port that cannot be served, a ``--context`` broker not reached or
refusing the connection); 3 stopped after recording faults. ``--exit-file PATH`` records the status and the
number of faults as one line ``EXIT_CODE FAULTS``.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import tempfile
import threading
import traceback
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import FrameType, ModuleType
from typing import TYPE_CHECKING

from acordcs.errors import AcordError
from acordcs.runtime.broker_setting import BrokerSetting, open_broker
from acordcs.runtime.clock import Clock, RealClock, VirtualClock
from acordcs.runtime.errors import RemoteNotGivenError, RuntimeFailure
from acordcs.runtime.launch_options import (
    EXIT_FAULTS,
    EXIT_NOT_STARTED,
    EXIT_OK,
    EXIT_RUN_FAILED,
    console_options,
    container_parser,
    exit_file_given,
)
from acordcs.runtime.live.code_check import hosted_here, operations_without_code
from acordcs.runtime.run_arguments import RunCall, RunError, bind_run

if TYPE_CHECKING:
    from acordcs.descriptor import Application
    from acordcs.runtime.assembly import RunningApplication
    from acordcs.runtime.connectors.endpoint import ContainerServer
    from acordcs.runtime.container import Container
    from acordcs.runtime.context.core import ProviderCore

DEFAULT_DURATION = 10.0  # virtual seconds run when --duration is not given

RUN_START_WINDOW = 0.5
"""Seconds (wall time) a container served on a real clock gives its --run operations before it
says it serves: one that fails within them fails the start (the container stops before that
line, which bin/<Container>-start waits for, so the script reports it as not started)."""


@dataclass
class _Runs:
    """The --run operations' outcome: the failures to report; ``stop`` is set by the first;
    ``running``, the calls under way (``changed`` notified when one ends); the lines of calls
    that returned before the container said it serves (``pending``, printed after that line:
    ``announced``)."""

    failed: list[str] = field(default_factory=list)
    stop: threading.Event = field(default_factory=threading.Event)
    running: int = 0
    changed: threading.Condition = field(default_factory=threading.Condition)
    announced: bool = True
    pending: list[str] = field(default_factory=list)

    def say(self, line: str) -> None:
        with self.changed:
            if not self.announced:
                self.pending.append(line)
                return
        print(line, flush=True)


class Launcher:
    """Runs the container ``container`` of the generated package ``package`` (its module is
    ``<package>.<container>``; its classes are in ``<package>.registry``, its descriptor in
    ``<package>/descriptor.xml``)."""

    def __init__(self, package: str, container: str) -> None:
        self.package = package
        self.container = container
        self.prog = f"python -m {package}.{container}"

    # ------------------------------------------------------------------------- assembling
    def descriptor_path(self) -> Path:
        """The package's ``descriptor.xml``."""
        module = importlib.import_module(self.package)
        return Path(module.__file__ or ".").with_name("descriptor.xml")

    def descriptor(self) -> Application:
        """The package's descriptor, read and validated; raises DescriptorError (file, line,
        column) or OSError."""
        return self._read()[1]

    def _read(self) -> tuple[bytes, Application]:
        from acordcs.descriptor import from_xml

        path = self.descriptor_path()
        data = path.read_bytes()
        return data, from_xml(data, file=str(path))

    def registry(self) -> ModuleType:
        """``<package>.registry``: importing it imports the component and monitor classes."""
        return importlib.import_module(f"{self.package}.registry")

    def assemble(
        self,
        clock: Clock | None = None,
        remote: Mapping[str, str] | None = None,
        remote_timeout: float = 5.0,
        *,
        application: Application | None = None,
        context: ProviderCore | None = None,
        state_dir: Path | None = None,
    ) -> RunningApplication:
        """The container assembled from the descriptor (``application``, default: read from the
        package) with the package's classes; ``remote``: the URI of each other container its
        connections reach (``PYRO:acordcs.container.<name>@host:port``); ``context``: its context
        provider (default: an embedded one), closed with it; ``state_dir``: where its persistent
        components' state is kept (None: not kept)."""
        shared: dict[str, object] = {} if context is None else {"context": context}
        if state_dir is not None:
            shared["state_dir"] = state_dir
        running: RunningApplication = self.registry().assemble_application(
            only=[self.container],
            clock=clock,
            remote=remote,
            remote_timeout=remote_timeout,
            application=application,
            **shared,
        )
        if context is not None:
            running.release(context.close)
        return running

    # ----------------------------------------------------------------------- command line
    def parser(self) -> argparse.ArgumentParser:
        return container_parser(self.prog, self.package, self.container)

    def main(self, argv: Sequence[str] | None = None) -> int:
        """Run the container as the command line ``argv`` (default: ``sys.argv[1:]``) says; the
        exit status (see the module's docstring)."""
        argv = list(sys.argv[1:] if argv is None else argv)
        parser = self.parser()
        try:
            args = parser.parse_args(argv)
            console_options(parser, args)
            if isinstance(args.context, BrokerSetting) and args.clock != "real":
                parser.error(f"--context {args.context} needs --clock real (the broker's "
                             "documents come in wall time)")  # fmt: skip
        except SystemExit as exc:
            if exc.code not in (0, None):  # a usage error, which the exit file says if given
                given = exit_file_given(argv)
                if given is not None:
                    self._write_exit_file(given, EXIT_NOT_STARTED, 0)
            raise
        if args.exit_file is not None:
            args.exit_file.unlink(missing_ok=True)  # a file there is this run's, once it stops
        # What the exit file says if _run raises (a bug: the interpreter then exits 1 too).
        code, faults = EXIT_RUN_FAILED, 0
        try:
            code, faults = self._run(args)
        finally:
            if args.exit_file is not None:
                self._write_exit_file(args.exit_file, code, faults)
        return code

    # ---------------------------------------------------------------------------- running
    def _say(self, message: str) -> None:
        print(f"{self.prog}: {message}", file=sys.stderr, flush=True)

    def _run(self, args: argparse.Namespace) -> tuple[int, int]:
        """Start, run and stop the container: (exit status, faults recorded)."""
        signal.signal(signal.SIGTERM, _interrupt)  # kill, bin/*-stop: stop as on Ctrl-C
        try:
            return self._start(args)
        except KeyboardInterrupt:  # the run loop has its own: this one came while starting
            self._say("interrupted while starting: not started")
            return EXIT_NOT_STARTED, 0

    def _start(self, args: argparse.Namespace) -> tuple[int, int]:
        from acordcs.descriptor import DescriptorError

        try:
            data, application = self._read()
        except DescriptorError as err:
            self._say(f"{err}")
            self._say(
                "the package's descriptor is refused: rebuild the package (acordcs-gen build)"
            )
            return EXIT_NOT_STARTED, 0
        except OSError as err:
            self._say(f"cannot read the descriptor: {err}")
            return EXIT_NOT_STARTED, 0
        found = next((c for c in application.containers if c.name == self.container), None)
        if found is None:
            self._say(
                f"the descriptor has no container {self.container!r} (containers: "
                f"{', '.join(c.name for c in application.containers) or 'none'}): rebuild the "
                "package (acordcs-gen build)"
            )
            return EXIT_NOT_STARTED, 0
        try:
            args.run = _bound(application, self.container, args.run)
        except RunError as err:
            self._say(f"{err}")
            return EXIT_NOT_STARTED, 0
        if args.state_dir is None:
            hosted = hosted_here(application, self.container, "component")
            kept = [c.name for c in application.components if c.persistent and c.name in hosted]
            if kept:
                self._say(f"the state of {', '.join(kept)} (tagged persistent) is not kept: no "
                          "--state-dir given (bin/<Container>-start gives the run directory)")  # fmt: skip
        problem = self._import_problem()
        if problem is not None:
            self._say(problem)
            return EXIT_NOT_STARTED, 0
        code = None
        if args.serve is not None:  # the user's files as imported: acordcs-gen update reads it
            from acordcs.runtime.live.reloading import PackageClasses

            hosted = hosted_here(application, self.container, "component")
            hosted += hosted_here(application, self.container, "monitor")
            code = PackageClasses(self.package).code(hosted)
        context = None
        if isinstance(args.context, BrokerSetting):
            try:
                context = open_broker(args.context, self.container, timeout=args.timeout,
                                      token=os.environ.get("ACORDCS_TOKEN"))  # fmt: skip
            except RuntimeFailure as err:
                self._say(f"{err}")
                return EXIT_NOT_STARTED, 0
        clock: Clock = VirtualClock(args.seed) if args.clock == "virtual" else RealClock()
        try:
            app = self.assemble(clock, dict(args.remote), args.timeout, application=application,
                                context=context, state_dir=args.state_dir)  # fmt: skip
        except AcordError as err:
            clock.close()
            if context is not None:
                context.close()
            self._say(f"{err}")
            others = [c.name for c in application.containers if c.name != self.container]
            if others and isinstance(err, RemoteNotGivenError):
                self._say(
                    f"the other containers: {', '.join(others)}; give the address of each one "
                    "this container reaches with --remote NAME=URI"
                )
            return EXIT_NOT_STARTED, 0
        with app:
            return self._started(app, args, found.host or "localhost", data, code)

    def _import_problem(self) -> str | None:
        """None when the package's classes import; else what failed, where (the last line of
        the package's code on the way), and what to do."""
        try:
            self.registry()
        except SyntaxError as err:
            where = f"{err.filename}:{err.lineno}" + (f":{err.offset}" if err.offset else "")
            return f"{where}: error: {err.msg}: fix the syntax there"
        except Exception as err:
            root = self.descriptor_path().parent
            frames = [
                f for f in traceback.extract_tb(err.__traceback__) if _under(f.filename, root)
            ]
            where = f"{frames[-1].filename}:{frames[-1].lineno}" if frames else str(root)
            return (
                f"{where}: error: importing the application's classes failed: "
                f"{type(err).__name__}: {err}: fix the code there (components/ and monitors/ are "
                "yours; a generated file that is missing or stale: acordcs-gen build)"
            )
        return None

    def _started(
        self,
        app: RunningApplication,
        args: argparse.Namespace,
        host: str,
        data: bytes,
        code: dict[str, dict[str, str]] | None,
    ) -> tuple[int, int]:
        container = app.container(self.container)
        unknown = _unknown_run(container, args.run)
        if unknown is not None:
            self._say(unknown)
            return EXIT_NOT_STARTED, 0
        calls = [(r.component, r.operation) for r in args.run]
        missing = operations_without_code(app, self.container, calls)
        for item in missing:
            print(item.message(), file=sys.stderr, flush=True)
        if missing and args.strict:
            self._say(
                f"not started (--strict): {len(missing)} operation(s) that the model calls have "
                "no code (listed above)"
            )
            return EXIT_NOT_STARTED, 0
        server = None
        if args.serve is not None:
            try:
                server = app.serve(self.container, host=args.host or host, port=args.serve)
            except RuntimeFailure as err:
                self._say(f"{err}")
                return EXIT_NOT_STARTED, 0
        runs = _Runs()
        clock = app.clock
        stop_console = None
        try:  # from here on, an interrupt stops it as a run's end does
            management = None
            if server is not None:
                from acordcs.runtime.live.management_server import manage
                from acordcs.runtime.live.reloading import PackageClasses

                classes = PackageClasses(self.package)
                management = manage(app, self.container, server, data, classes, dict(args.remote),
                                    without_token=args.updates_without_token, timeout=args.timeout,
                                    code=code, announce=False)  # fmt: skip
            if isinstance(clock, VirtualClock):
                if server is not None and management is not None:
                    self._announce(server.uri, management.digest, runs)
                for call in args.run:  # in turn: simulated time is one thread's
                    if not runs.stop.is_set():
                        self._call(container, call, runs)
                if not runs.stop.is_set():
                    until = DEFAULT_DURATION if args.duration is None else args.duration
                    clock.run_until(max(clock.now(), until))
            else:
                runs.announced = server is None
                for call in args.run:
                    with runs.changed:
                        runs.running += 1
                    threading.Thread(target=self._call, args=(container, call, runs),
                                     name=f"run {call.component}.{call.operation}", daemon=True).start()  # fmt: skip
                if server is not None and management is not None:
                    # The start-up: the --run calls' first moments; one failing fails the start.
                    with runs.changed:
                        runs.changed.wait_for(
                            lambda: runs.running == 0 or runs.stop.is_set(),
                            timeout=RUN_START_WINDOW if args.run else 0,
                        )
                    if not runs.stop.is_set():
                        self._announce(server.uri, management.digest, runs)
                if args.console is not None and server is not None and not runs.stop.is_set():
                    stop_console = self._console(app, server, args.console)
                if runs.stop.is_set():
                    pass  # a --run failed during the start-up: stopped before saying it serves
                elif args.duration is not None:
                    runs.stop.wait(args.duration)
                else:
                    while not runs.stop.wait(3600):
                        pass
        except KeyboardInterrupt:
            pass
        # Stopping: a second TERM or Ctrl-C is ignored (KILL is not).
        for signum in (signal.SIGTERM, signal.SIGINT):
            signal.signal(signum, signal.SIG_IGN)
        runs.stop.set()  # a --run operation failing from now on is the stop's doing, not reported
        if stop_console is not None:
            stop_console()
        for line in list(runs.failed):
            self._say(line)
        faults = container.faults.counts["total"]
        print(f"{self.container}: stopped at t={clock.now():.3f} s, faults: {faults}", flush=True)
        if runs.failed:
            return EXIT_RUN_FAILED, faults
        return (EXIT_FAULTS if faults and not args.faults_ok else EXIT_OK), faults

    def _console(
        self, app: RunningApplication, server: ContainerServer, port: int
    ) -> Callable[[], None] | None:
        """Serve this container's browser console (:mod:`.console_hook`); what stops it, or None
        when it could not start (said)."""
        from acordcs.runtime.console_hook import console_server

        token = os.environ.get("ACORDCS_TOKEN") if server.token_required else None
        try:
            return console_server()(app.descriptor, self.container, (server.host, server.port),
                                    token, port, lambda line: print(line, flush=True))  # fmt: skip
        except (OSError, RuntimeError) as err:  # the console's AttachError is a RuntimeError
            self._say(f"the console did not start: {err}")
            return None

    def _announce(self, uri: str, digest: str, runs: _Runs) -> None:
        """The lines saying the container serves, at the end of its start-up (what its start
        script waits for), then those of the --run calls that returned before."""
        from acordcs.runtime.live.management_server import say_digest

        print(f"{self.container}: serving at {uri}", flush=True)
        say_digest(self.container, digest, "runs")
        with runs.changed:
            runs.announced = True
            pending, runs.pending = runs.pending, []
        for line in pending:
            print(line, flush=True)

    def _call(self, container: Container, call: RunCall, runs: _Runs) -> None:
        """A --run operation, called through the container (its interceptors and monitors see
        the call) with its arguments; a failure is reported in ``runs`` and stops the
        container."""
        what = call.text
        try:
            try:
                result = container.find(call.component).call(call.operation, *call.values)
            except Exception as err:  # reported (what, where, when), never a traceback
                if not runs.stop.is_set():
                    runs.failed.append(
                        f"--run {what} failed at t={container.clock.now():.3f} s: {err}"
                    )
                    runs.stop.set()
                return
            runs.say(f"{self.container}: --run {what} returned {result!r:.200} at "
                     f"t={container.clock.now():.3f} s")  # fmt: skip
        finally:
            with runs.changed:
                runs.running = max(runs.running - 1, 0)
                runs.changed.notify_all()

    def _write_exit_file(self, path: Path, code: int, faults: int) -> None:
        """``EXIT_CODE FAULTS`` into ``path``, replacing it at once (a reader sees the old file or
        the new one, never a part), mode 0600."""
        try:
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            try:
                with os.fdopen(fd, "w", encoding="ascii") as out:
                    out.write(f"{code} {faults}\n")
                os.replace(tmp, path)
            except BaseException:
                os.unlink(tmp)
                raise
        except OSError as err:
            self._say(f"cannot write the exit file {path}: {err}")


def _bound(application: Application, container: str, runs: list[RunCall]) -> list[RunCall]:
    """The --run calls with their arguments typed by the model's operations (see
    :mod:`acordcs.runtime.run_arguments`); RunError for a component not hosted here or an
    argument that does not fit. An operation the model does not declare is checked once the
    container is assembled (:func:`_unknown_run`: the class may have it)."""
    hosted = hosted_here(application, container, "component")
    components = {c.name: c for c in application.components if c.name in hosted}
    out = []
    for call in runs:
        found = components.get(call.component)
        if found is None:
            raise RunError(
                f"--run {call.written}: container {container} hosts no component "
                f"{call.component!r} (it hosts: {', '.join(sorted(hosted)) or 'nothing'})"
            )
        operation = next((op for op in found.operations if op.name == call.operation), None)
        out.append(bind_run(call, operation))
    return out


def _under(filename: str, root: Path) -> bool:
    try:
        return Path(filename).resolve().is_relative_to(root.resolve())
    except OSError:
        return False


def _interrupt(signum: int, _frame: FrameType | None) -> None:
    raise KeyboardInterrupt


def _unknown_run(container: Container, runs: list[RunCall]) -> str | None:
    """What is wrong with the --run operations (None: each names an operation hosted here)."""
    for call in runs:
        component, operation = call.component, call.operation
        ops = container.operations_of(component)
        if not ops:
            hosted = ", ".join(c.name for c in container.components()) or "nothing"
            return (
                f"--run {component}.{operation}: container {container.name} hosts no component "
                f"{component!r} (it hosts: {hosted})"
            )
        if operation not in ops:
            return (
                f"--run {component}.{operation}: component {component!r} has no operation "
                f"{operation!r} (operations: {', '.join(sorted(ops))})"
            )
    return None


__all__ = ["Launcher"]
