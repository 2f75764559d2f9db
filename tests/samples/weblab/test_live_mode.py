"""Live mode (``make live``, ``samples/weblab/live.sh``): the generated WebLab application started
by its generated scripts as two OS processes on free loopback ports, in real time, the user's
running ``Navigator.run`` (``ACORDCS_UserSide_RUN``) against the WebLab's over Pyro5: frames
arrive as bytes, moves reach the robot, the SpeedLimiting policy sets ``Locomotion.maxSpeed`` in
the WebLab's process, both stop with no fault; Ctrl-C stops both as well. About 15 s each."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
from pathlib import Path

from tests.generator.test_shell_scripts_parse_quote_and_run import free_ports
from tests.samples.weblab.conftest import APP_DIR, SAMPLE_DIR
from tests.support.toolchain import ROOT

LIVE = SAMPLE_DIR / "live.sh"


def environment(run: Path, seconds: int) -> dict[str, str]:
    user, lab = free_ports(2)
    return {
        **os.environ,
        "PYTHON": sys.executable,
        "PYTHONPATH": str(ROOT / "src"),
        "ACORDCS_RUN_DIR": str(run),
        "ACORDCS_UserSide_PORT": str(user),
        "ACORDCS_WebLabSide_PORT": str(lab),
        "ACORDCS_STOP_TIMEOUT": "5",
        "WEBLAB_LIVE_SECONDS": str(seconds),
    }


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    state = subprocess.run(["ps", "-o", "stat=", "-p", str(pid)], capture_output=True, text=True)
    return not state.stdout.strip().startswith("Z") and state.stdout.strip() != ""


def cleanup(env: dict[str, str], run: Path) -> None:
    """Whatever happened: stop-all, then KILL any container process still there."""
    subprocess.run(["sh", str(APP_DIR / "bin" / "stop-all")], env=env, capture_output=True,
                   timeout=60)  # fmt: skip
    for name in ("UserSide", "WebLabSide"):
        pidfile = run / f"{name}.pid"
        if pidfile.exists():
            pid = int(pidfile.read_text().strip() or 0)
            if pid and alive(pid):
                os.kill(pid, signal.SIGKILL)


def pids(output: str) -> tuple[int, int]:
    found = re.search(r"live: processes: (\d+) \(UserSide\), (\d+) \(WebLabSide\)", output)
    assert found, output
    return int(found[1]), int(found[2])


def test_a_short_live_run_over_pyro5_on_loopback(weblab_app: None, tmp_path: Path) -> None:
    run = tmp_path / "run"
    env = environment(run, 12)
    try:
        done = subprocess.run(["sh", str(LIVE)], env=env, capture_output=True, text=True,
                              timeout=180)  # fmt: skip
    finally:
        cleanup(env, run)
    out = done.stdout + done.stderr
    assert done.returncode == 0, out
    user_pid, lab_pid = pids(out)
    assert len({user_pid, lab_pid, os.getpid()}) == 3
    assert not alive(user_pid) and not alive(lab_pid)
    user = (run / "UserSide.log").read_text()
    lab = (run / "WebLabSide.log").read_text()
    # Each serves on loopback at its port; the user's reaches the WebLab's over Pyro5.
    for name, log in (("UserSide", user), ("WebLabSide", lab)):
        port = env[f"ACORDCS_{name}_PORT"]
        assert f"{name}: serving at PYRO:acordcs.container.{name}@127.0.0.1:{port}" in log, log
        assert re.search(rf"^{name}: stopped at t=[\d.]+ s, faults: 0$", log, re.M), log
    # The Navigator's run ended at the time cap (or the finish line) after several cycles, each
    # frame arriving as bytes, and the robot moved: the moves reached it.
    summary = re.search(
        r"^Navigator: (?:time cap of 12 s reached|finish line crossed): (\d+) cycles in "
        r"([\d.]+) s = ([\d.]+) cycles/s \((\d+) moving\), \d+ stripe losses, distance (\d+) mm, "
        r"progress \d+ mm, (\d+) frames as bytes of (\d+) B on average$",
        user,
        re.M,
    )
    assert summary, user
    cycles, elapsed, _rate, moving, distance, frames, size = summary.groups()
    assert int(cycles) >= 5 and int(moving) >= 1 and float(elapsed) >= 5.0
    assert int(frames) == int(cycles) and int(size) > 500
    assert int(distance) > 100
    assert "UserSide: --run Navigator.run() returned None at t=" in user
    # In the WebLab's process: the status lines, with the cap the speed policy set (the model's
    # default is 200) and the cycle rate the Control monitor measured from the remote moves.
    status = re.findall(
        r"^WebLab t=.*Control: cycleRate ([\d.]+)/s.*SpeedLimiting: maxSpeed +([\d.]+) mm/s",
        lab,
        re.M,
    )
    assert status, lab
    assert all(float(rate) > 0.5 for rate, _ in status)
    assert all(float(cap) < 200.0 for _, cap in status)
    assert "faults: UserSide 0, WebLabSide 0" in done.stdout
    assert "live: done: the Navigator completed its run over Pyro5" in done.stdout


# What a terminal's shell does for a foreground job: SIGINT and SIGTERM at their defaults. A shell
# started with SIGINT ignored cannot trap it (POSIX), and pytest may run with it ignored (a
# background job of a non-interactive shell): then Ctrl-C never reached live.sh, which drove on
# to the finish line. The test starts live.sh as a terminal would.
AS_A_TERMINAL_WOULD = (
    "import os, signal, sys\n"
    "signal.signal(signal.SIGINT, signal.SIG_DFL)\n"
    "signal.signal(signal.SIGTERM, signal.SIG_DFL)\n"
    "os.execvp('sh', ['sh', sys.argv[1]])\n"
)
READY = "live: running (Ctrl-C stops both)"


def test_ctrl_c_stops_both_processes(weblab_app: None, tmp_path: Path) -> None:
    run = tmp_path / "run"
    env = environment(run, 60)
    live = subprocess.Popen([sys.executable, "-c", AS_A_TERMINAL_WOULD, str(LIVE)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)  # fmt: skip
    lines: list[str] = []
    ready = threading.Event()

    def read() -> None:
        assert live.stdout is not None
        for line in live.stdout:
            lines.append(line)
            if line.rstrip("\n") == READY:
                ready.set()
        ready.set()  # the end of the output: never ready

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        # its processes started and its traps set: the readiness line, not a delay
        assert ready.wait(120) and live.poll() is None, "".join(lines)
        os.killpg(live.pid, signal.SIGINT)  # what Ctrl-C in a terminal does
        live.wait(timeout=60)
        reader.join(10)
    finally:
        if live.poll() is None:
            os.killpg(live.pid, signal.SIGKILL)
            live.wait()
        cleanup(env, run)
    out = "".join(lines)
    assert live.returncode == 130, out
    assert "live: interrupted" in out and "is ignored in this shell" not in out
    # The user's process first (its Navigator is mid-run), then stop-all.
    assert out.index("UserSide: stopped (pid") < out.index("WebLabSide: stopped (pid")
    user_pid, lab_pid = pids(out)
    assert not alive(user_pid) and not alive(lab_pid)
    for name in ("UserSide", "WebLabSide"):
        assert not (run / f"{name}.pid").exists()
        assert f"{name}: stopped at t=" in (run / f"{name}.log").read_text()


def test_live_says_when_ctrl_c_cannot_reach_it(tmp_path: Path) -> None:
    # started with SIGINT ignored, live.sh says so before anything else (its app dir is empty here,
    # so it stops at once after that)
    app = tmp_path / "weblab"
    (app / "app" / "bin").mkdir(parents=True)
    (app / "live.sh").write_bytes(LIVE.read_bytes())
    (app / "app" / "bin" / "start-all").write_text("exit 1\n")
    (app / "app" / "bin" / "stop-all").write_text("exit 0\n")
    (app / "app" / "bin" / "UserSide-stop").write_text("exit 0\n")
    ignoring = "import os, signal, sys\nsignal.signal(signal.SIGINT, signal.SIG_IGN)\n"
    ignoring += "os.execvp('sh', ['sh', sys.argv[1]])\n"
    done = subprocess.run([sys.executable, "-c", ignoring, str(app / "live.sh")],
                          env={**os.environ, "ACORDCS_RUN_DIR": str(tmp_path / "run")},
                          capture_output=True, text=True, timeout=60)  # fmt: skip
    assert "live: SIGINT or SIGTERM is ignored in this shell" in done.stderr, done.stderr
    assert "kill -TERM" in done.stderr
    quiet = AS_A_TERMINAL_WOULD
    done = subprocess.run([sys.executable, "-c", quiet, str(app / "live.sh")],
                          env={**os.environ, "ACORDCS_RUN_DIR": str(tmp_path / "run")},
                          capture_output=True, text=True, timeout=60)  # fmt: skip
    assert "is ignored in this shell" not in done.stderr, done.stderr
