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
    """User and system CPU seconds of process ``pid`` so far (``/proc/<pid>/stat``)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _cpu_over(pid: int, seconds: float) -> float:
    """The share of a core (%) process ``pid`` used over the next ``seconds``."""
    before, t0 = cpu_seconds(pid), time.monotonic()
    time.sleep(seconds)
    return 100 * (cpu_seconds(pid) - before) / (time.monotonic() - t0)


def cpu_rounds(
    app: Greenhouse, window: float, rounds: int, viewers: Callable
) -> dict[str, list[float]]:
    """The greenhouse's CPU with no console, the console and 0 viewers, and 10 viewers (the
    ``viewers`` function of bench_console in a child process), ``rounds`` times each in turn."""
    found: dict[str, list[float]] = {"none": [], "console": [], "10 viewers": []}
    ctx = multiprocessing.get_context("spawn")
    for _ in range(rounds):
        found["none"].append(_cpu_over(app.pid, window))
        with console_on(app, watchers=10) as (url, hub):
            time.sleep(1.0)  # the watch settled
            found["console"].append(_cpu_over(app.pid, window))
            stop, ready = ctx.Event(), ctx.Event()
            ws = url.replace("http", "ws") + "/ws"
            child = ctx.Process(target=viewers, args=(ws, 10, ready, stop), daemon=True)
            child.start()
            ready.wait(30)
            deadline = time.monotonic() + 10
            while hub.viewers < 10 and time.monotonic() < deadline:
                time.sleep(0.05)
            found["10 viewers"].append(_cpu_over(app.pid, window))
            stop.set()
            child.join(10)
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
