"""The rig of ``bench_console.py``'s parts 3 and 4: the tutorial's greenhouse with its monitor at
10 Hz, built and started by its generated scripts (real clock, loopback, a run directory of its
own), the console of ``acordcs-gen console`` attached to it in this process, its process's CPU
measured from ``/proc``, and the time from a firing in the container to a page having it."""

from __future__ import annotations

import asyncio
import contextlib
import json
import multiprocessing
import os
import shutil
import socket
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import websockets

from acordcs.cli import main as acordcs_gen
from acordcs.console.fanout import ConsoleHub
from acordcs.console.in_thread import serving
from acordcs.console.live_session import LiveSession
from acordcs.console.site_guard import allowed_names
from acordcs.console.web_app import console_refusals, create_app

ROOT = Path(__file__).resolve().parents[1]
GREENHOUSE = ROOT / "samples" / "tutorial"
TOKEN = "bench-console-token"


@dataclass
class Greenhouse:
    """The started greenhouse: its directory, the environment its scripts ran with, the pid of
    its one container's process."""

    out: Path
    env: dict[str, str]
    pid: int


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextlib.contextmanager
def greenhouse_at_10_hz(tmp: Path) -> Iterator[Greenhouse]:
    """The greenhouse (its monitor's frequency 1 -> 10 Hz) built in ``tmp``, started, stopped."""
    model = tmp / "greenhouse.uml"
    text = (GREENHOUSE / "greenhouse.uml").read_text(encoding="utf-8")
    faster = text.replace(
        'operation="readTemperature" frequency="1"', 'operation="readTemperature" frequency="10"'
    )
    assert faster != text, "the greenhouse's monitor frequency is not where it was"
    model.write_text(faster, encoding="utf-8")
    out = tmp / "app"
    code = out / "greenhouse_app" / "components"
    code.mkdir(parents=True)
    shutil.copyfile(
        GREENHOUSE / "app" / "greenhouse_app" / "components" / "Sensor.py", code / "Sensor.py"
    )
    assert (
        acordcs_gen(["build", "-q", str(model), "-o", str(out), "-t", "python", "-t", "shell"]) == 0
    )
    run = tmp / "run"
    run.mkdir(mode=0o700)
    env = {k: v for k, v in os.environ.items() if not k.startswith("ACORDCS_")}
    env.update(ACORDCS_RUN_DIR=str(run), ACORDCS_House_HOST="127.0.0.1",
               ACORDCS_House_PORT=str(_free_port()), PYTHON=sys.executable)  # fmt: skip
    subprocess.run(["sh", str(out / "bin" / "start-all")], env=env, check=True, capture_output=True)
    try:
        pid = int((run / "House.pid").read_text().strip())
        yield Greenhouse(out, env, pid)
    finally:
        subprocess.run(["sh", str(out / "bin" / "stop-all")], env=env, capture_output=True)


@contextlib.contextmanager
def console_on(app: Greenhouse, watchers: int = 0) -> Iterator[tuple[str, ConsoleHub]]:
    """The console attached to ``app`` in this process: its URL and hub."""
    saved = {k: os.environ.get(k) for k in app.env if k.startswith("ACORDCS_")}
    os.environ.update({k: v for k, v in app.env.items() if k.startswith("ACORDCS_")})
    hub = ConsoleHub(max_viewers=16, max_watchers=watchers)
    session = LiveSession.attached(hub, TOKEN, app.out)
    try:
        session.attach()
        site = session.site()
        refusals = console_refusals(site)
        served = create_app(site, hub, session, allowed_hosts=allowed_names("127.0.0.1"),
                            refusals=refusals)  # fmt: skip
        with serving(served, refusals) as url:
            yield url, hub
    finally:
        session.close()
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def cpu_seconds(pid: int) -> float:
    """User and system CPU seconds of process ``pid`` so far (``/proc/<pid>/stat``, in clock
    ticks of 10 ms)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


CPUACCT = Path("/sys/fs/cgroup/cpuacct")  # cgroup v1's CPU accounting, in nanoseconds


class CpuClock:
    """The CPU seconds process ``pid`` has used, all its threads (gone ones too): from a cgroup
    of its own under cgroup v1's ``cpuacct`` (nanoseconds) when this process may make one
    (root), else from ``/proc/<pid>/stat`` (10 ms ticks: at about 1 % of a core a 15 s window
    holds some 15 ticks, too coarse for a difference of 5 %). ``source`` says which."""

    def __init__(self, pid: int) -> None:
        self.pid, self.group = pid, CPUACCT / f"acordcs-bench-{pid}"
        try:
            self.group.mkdir()
            (self.group / "cgroup.procs").write_text(str(pid))
        except OSError:
            with contextlib.suppress(OSError):
                self.group.rmdir()
            self.group = None  # type: ignore[assignment]
        self.source = "cgroup cpuacct (ns)" if self.group else "/proc stat (10 ms ticks)"

    def seconds(self) -> float:
        if self.group is None:
            return cpu_seconds(self.pid)
        return int((self.group / "cpuacct.usage").read_text()) / 1e9

    def close(self) -> None:
        """The process back in the root group, and the group removed."""
        if self.group is not None:
            with contextlib.suppress(OSError):  # gone meanwhile: its group empties itself
                (CPUACCT / "cgroup.procs").write_text(str(self.pid))
            with contextlib.suppress(OSError):
                self.group.rmdir()


def wakeups(pid: int) -> int:
    """How many times the threads of process ``pid`` alive now gave up their core to wait so far
    (``voluntary_ctxt_switches`` of each ``/proc/<pid>/task/*/status``; the involuntary ones
    count the host's load): each request it serves, each timer it sleeps on, is one or more;
    the work it does, counted rather than timed."""
    total = 0
    for status in Path(f"/proc/{pid}/task").glob("*/status"):
        with contextlib.suppress(OSError):  # a thread that ended meanwhile
            for line in status.read_text().splitlines():
                if line.startswith("voluntary_ctxt_switches:"):
                    total += int(line.split()[1])
    return total


@dataclass(frozen=True)
class Window:
    """What the process did over one window, per second: ``cpu`` (% of a core), ``wakeups``
    (its threads' voluntary context switches), ``threads`` (at the window's end)."""

    cpu: float
    wakeups: float
    threads: int


def _window(clock: CpuClock, seconds: float) -> Window:
    """What the clock's process does over the next ``seconds``."""
    cpu0, woke0, t0 = clock.seconds(), wakeups(clock.pid), time.monotonic()
    time.sleep(seconds)
    cpu1, woke1, wall = clock.seconds(), wakeups(clock.pid), time.monotonic() - t0
    threads = len(list(Path(f"/proc/{clock.pid}/task").iterdir()))
    return Window(100 * (cpu1 - cpu0) / wall, (woke1 - woke0) / wall, threads)


# The 0.975 quantile of Student's t with 1..30 degrees of freedom (a table: the interval below
# needs nothing more, and scipy is not a dependency).
T975 = (12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179,
        2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
        2.060, 2.056, 2.052, 2.048, 2.045, 2.042)  # fmt: skip


@dataclass
class CpuPairs:
    """The greenhouse's windows: ``none`` before any console, then, with the console attached
    throughout, ``zero`` and ``ten`` viewers, window ``i`` of each one pair (run back to back,
    the order alternating pair by pair); ``source``: where its CPU time was read."""

    none: list[Window]
    zero: list[Window]
    ten: list[Window]
    source: str

    def mean(self, kind: str, what: str) -> float:
        """The mean of ``what`` (a field of :class:`Window`) over the windows of ``kind``."""
        return statistics.fmean(getattr(w, what) for w in getattr(self, kind))

    def difference(self, what: str = "cpu") -> tuple[float, float, float]:
        """10 viewers against 0 in ``what``, as % of the 0-viewer mean: the mean of the pairs'
        differences and its 95 % confidence interval (Student's t over the pairs)."""
        diffs = [
            getattr(t, what) - getattr(z, what) for t, z in zip(self.ten, self.zero, strict=True)
        ]
        base, mean = self.mean("zero", what), statistics.fmean(diffs)
        half = (
            T975[min(len(diffs), len(T975) + 1) - 2] * statistics.stdev(diffs) / len(diffs) ** 0.5
        )
        return tuple(100 * v / base for v in (mean, mean - half, mean + half))  # type: ignore[return-value]


def cpu_pairs(app: Greenhouse, window: float, pairs: int, viewers: Callable) -> CpuPairs:
    """The greenhouse's CPU with no console (two windows), then with the console attached once
    and, ``pairs`` times, a window with 0 viewers and one with 10 (the ``viewers`` function of
    bench_console in a child process, connected before its window starts and gone before the
    next), in alternating order so that a drift of the host's load falls on both alike."""
    settle = 2.0  # seconds after the viewers came or went, before a window opens
    clock = CpuClock(app.pid)
    found = CpuPairs([_window(clock, window) for _ in range(2)], [], [], clock.source)
    ctx = multiprocessing.get_context("spawn")
    with contextlib.closing(clock), console_on(app, watchers=10) as (url, hub):
        time.sleep(settle)  # the watch settled
        ws = url.replace("http", "ws") + "/ws"
        for i in range(pairs):
            for viewed in (False, True) if i % 2 == 0 else (True, False):
                if not viewed:
                    found.zero.append(_window(clock, window))
                    continue
                stop, ready = ctx.Event(), ctx.Event()
                child = ctx.Process(target=viewers, args=(ws, 10, ready, stop), daemon=True)
                child.start()
                ready.wait(30)
                deadline = time.monotonic() + 10
                while hub.viewers < 10 and time.monotonic() < deadline:
                    time.sleep(0.05)
                time.sleep(settle)
                found.ten.append(_window(clock, window))
                stop.set()
                child.join(10)
                deadline = time.monotonic() + 10
                while hub.viewers and time.monotonic() < deadline:
                    time.sleep(0.05)
                time.sleep(settle)
    return found


def firing_latency(app: Greenhouse, seconds: float) -> list[float]:
    """Milliseconds from each firing on the container's clock to a page holding the token
    having it, for ``seconds``."""
    with console_on(app) as (url, _):
        # The container's clock against this process's: both CLOCK_MONOTONIC, the offset from the
        # management interface's status (its time, at the round trip's midpoint), best of 20.
        from acordcs.console.attaching import Application

        saved = {k: os.environ.get(k) for k in app.env if k.startswith("ACORDCS_")}
        os.environ.update({k: v for k, v in app.env.items() if k.startswith("ACORDCS_")})
        session_app = None
        try:
            session_app = Application.built_in(app.out, 5.0)
            best = None
            for _ in range(20):
                t0 = time.monotonic()
                there = session_app.manage("House", "status")["time"]
                t1 = time.monotonic()
                if best is None or t1 - t0 < best[0]:
                    best = (t1 - t0, there - (t0 + t1) / 2)
            assert best is not None
            offset = best[1]
        finally:
            if session_app is not None:
                session_app.close()
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        return asyncio.run(_page(url.replace("http", "ws") + "/ws", offset, seconds))


async def _page(url: str, offset: float, seconds: float) -> list[float]:
    seen: list[float] = []
    async with websockets.connect(url, subprotocols=["acordcs", f"acordcs.token.{TOKEN}"]) as ws:
        end = time.monotonic() + seconds
        started = False
        while time.monotonic() < end:
            try:
                raw = await asyncio.wait_for(ws.recv(), timeout=1.0)
            except TimeoutError:
                continue
            now = time.monotonic()
            message = json.loads(raw)
            for m in message if isinstance(message, list) else [message]:
                data = m.get("data") if m.get("type") == "event" else None
                # The first message holds the recent past a joiner is given: not timed.
                if started and isinstance(data, dict) and data.get("kind") == "fired":
                    seen.append(1000 * (now - (data["time"] - offset)))
            started = True
    return seen
