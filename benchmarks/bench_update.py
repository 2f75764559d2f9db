"""``acordcs-gen update`` on the live WebLab (standalone; prints figures, asserts nothing). About a
minute.

The generated WebLab started by its scripts as two processes on loopback in real time (as ``make
live``), the robot driving; then, alternately, SpeedLimiting's rule for narrow turns at a large
cycle rate (the rate on loopback) set to ``slow`` and back to ``fast``, each by ``acordcs-gen
update`` run as a user runs it. Per update:

- **invoked to first fired**: from the command started to the first firing of SpeedLimiting on the
  new rules in the WebLab's process (the time its management interface records, on the machine's
  monotonic clock, the one this process reads). Target: p50 under 1 s, most of it the build;
- **of which the command**: ``acordcs-gen update`` from its start to its exit (the rest is the
  wait for the set's next triggering event: the control loop's next cycle);
- **the build alone**: ``acordcs-gen build`` of the same model changes, timed on its own (what
  the update does besides reaching the containers and applying);
- **apply in the container**: what the WebLab's container spent on its part (the new engine built
  beside the running one, then swapped in);
- **pause**: the gap between SpeedLimiting's last firing before the update started and its first
  after it, against the set's usual gap between firings (the control loop's period). Target: no
  more than one period more, i.e. no firing lost to the update.

Usage: python benchmarks/bench_update.py [--updates N]  (the generated application must be built:
``acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from acordcs.runtime.connectors.remote import RemoteConnector
from acordcs.runtime.live.management import MANAGE_OBJECT

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "weblab"
FAST = "largeNarrow: if cycleRate is large and angle is narrow then Locomotion.maxSpeed is fast"
SLOW = FAST.replace("is fast", "is slow")
GEN = Path(sys.executable).with_name("acordcs-gen")


def free_ports(count: int) -> list[int]:
    sockets = [socket.socket() for _ in range(count)]
    try:
        for s in sockets:
            s.bind(("127.0.0.1", 0))
        return [s.getsockname()[1] for s in sockets]
    finally:
        for s in sockets:
            s.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--updates", type=int, default=9)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-update-") as scratch:
        return run(Path(scratch), args.updates)


def run(root: Path, updates: int) -> int:
    app, runs = root / "app", root / "run"
    shutil.copytree(SAMPLE / "app", app, ignore=shutil.ignore_patterns("run", "__pycache__"))
    runs.mkdir(mode=0o700)
    models_ = {}
    sample = (SAMPLE / "weblab.xmi").read_text(encoding="utf-8")
    for name, text in (("slow", sample.replace(FAST, SLOW)), ("fast", sample)):
        # the rule is in both places BOUML writes a tag: the class's and the stereotype's
        assert name == "fast" or sample.count(FAST) == 2
        folder = root / name
        folder.mkdir()
        models_[name] = folder / "weblab.xmi"
        models_[name].write_text(text, encoding="utf-8")
    user, lab = free_ports(2)
    env = {
        **{k: v for k, v in os.environ.items() if not k.startswith("ACORDCS_")},
        "PYTHON": sys.executable,
        "PYTHONPATH": os.pathsep.join([str(SAMPLE), str(ROOT / "src")]),
        "ACORDCS_RUN_DIR": str(runs),
        "ACORDCS_CLOCK": "real",
        "ACORDCS_UserSide_HOST": "127.0.0.1",
        "ACORDCS_WebLabSide_HOST": "127.0.0.1",
        "ACORDCS_UserSide_PORT": str(user),
        "ACORDCS_WebLabSide_PORT": str(lab),
        "ACORDCS_UserSide_RUN": "Navigator.run",
        "ACORDCS_TIMEOUT": "30",
        "ACORDCS_STOP_TIMEOUT": "5",
        "WEBLAB_TIME_CAP": "600",
        "WEBLAB_FORWARD_SPEED": "200",
    }
    subprocess.run([str(GEN), "build", "-q", str(models_["slow"]), "-o", str(app)], check=True)
    subprocess.run(["sh", str(app / "bin" / "start-all")], env=env, check=True,
                   stdout=subprocess.DEVNULL)  # fmt: skip
    try:
        token = (runs / "token").read_text().strip()
        uri = f"PYRO:{MANAGE_OBJECT.format('WebLabSide')}@127.0.0.1:{lab}"
        connector = RemoteConnector(timeout=10.0, token=token)

        def status() -> dict:
            return connector.request(uri, "status", where="bench")  # type: ignore[no-any-return]

        while status()["policy_sets"]["SpeedLimiting"]["fires"] < 10:
            time.sleep(0.1)
        rows = []
        for i in range(updates):
            model = models_["fast" if i % 2 == 0 else "slow"]
            period = firing_period(status)
            invoked = time.monotonic()
            done = subprocess.run([str(GEN), "update", str(model), "-o", str(app)], env=env,
                                  capture_output=True, text=True, check=False)  # fmt: skip
            returned = time.monotonic()
            if done.returncode != 0:
                print(done.stdout + done.stderr)
                return 1
            taken = wait_first_firing(status)
            offset = time.monotonic() - status()["time"]  # the container's clock on ours
            fired = taken["first_fired"]["SpeedLimiting"] + offset
            seconds = float(done.stdout.split("WebLabSide: applied 1 change in ")[1].split()[0])
            pause = taken["first_fired"]["SpeedLimiting"] - taken["fired_before"]["SpeedLimiting"]
            rows.append((fired - invoked, seconds / 1000, pause, period, returned - invoked))
            time.sleep(0.5)
        builds = []
        for i in range(updates):  # the same builds, alone (each writes what the model changed)
            model = models_["fast" if i % 2 == 1 else "slow"]
            started = time.perf_counter()
            subprocess.run([str(GEN), "build", str(model), "-o", str(app)], capture_output=True,
                           check=True)  # fmt: skip
            builds.append(time.perf_counter() - started)
        connector.close()
    finally:
        subprocess.run(["sh", str(app / "bin" / "stop-all")], env=env, capture_output=True,
                       check=False)  # fmt: skip
    report(rows, builds)
    return 0


def firing_period(status) -> float:
    """SpeedLimiting's usual gap between firings: over two seconds of its firings."""
    first = status()["policy_sets"]["SpeedLimiting"]
    time.sleep(2.0)
    last = status()["policy_sets"]["SpeedLimiting"]
    return (last["time"] - first["time"]) / max(last["fires"] - first["fires"], 1)


def wait_first_firing(status) -> dict:
    deadline = time.monotonic() + 30
    while True:
        taken = status()["last_update"]
        if taken and "SpeedLimiting" in taken["first_fired"]:
            return taken  # type: ignore[no-any-return]
        if time.monotonic() > deadline:
            raise SystemExit("SpeedLimiting did not fire within 30 s of the update")
        time.sleep(0.01)


def report(rows: list[tuple[float, ...]], builds: list[float]) -> None:
    def p(values: list[float], q: float) -> float:
        ordered = sorted(values)
        return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]

    first = [r[0] for r in rows]
    apply = [r[1] for r in rows]
    pauses = [r[2] for r in rows]
    periods = [r[3] for r in rows]
    commands = [r[4] for r in rows]
    period = statistics.median(periods)
    print(f"acordcs-gen update on the live WebLab (two processes, loopback), {len(rows)} updates "
          "of SpeedLimiting's largeNarrow rule, alternately slow and fast")  # fmt: skip
    print(f"  invoked to first fired on the new rules: p50 {p(first, 0.5) * 1000:6.0f} ms, "
          f"p95 {p(first, 0.95) * 1000:6.0f} ms (target: p50 under 1000 ms)")  # fmt: skip
    print(f"  of which the command (acordcs-gen update, to its exit): p50 "
          f"{p(commands, 0.5) * 1000:6.0f} ms; the rest: the set's next event")  # fmt: skip
    print(f"  the same model change built alone (acordcs-gen build): p50 "
          f"{p(builds, 0.5) * 1000:6.0f} ms ({p(builds, 0.5) / p(first, 0.5):.0%} of the "
          "first figure)")  # fmt: skip
    print(f"  apply in the WebLab's container: p50 {p(apply, 0.5) * 1000:6.1f} ms, "
          f"max {max(apply) * 1000:6.1f} ms (the old engine fires meanwhile)")  # fmt: skip
    print(f"  pause: gap between the last firing before and the first after: p50 "
          f"{p(pauses, 0.5) * 1000:5.0f} ms, max {max(pauses) * 1000:5.0f} ms; the set's usual "
          f"gap {period * 1000:.0f} ms: {max(pauses) / period:.2f} periods at most "
          "(target: at most 2, i.e. no firing lost)")  # fmt: skip


if __name__ == "__main__":
    sys.exit(main())
