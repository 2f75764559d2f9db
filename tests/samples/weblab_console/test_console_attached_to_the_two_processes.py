"""``make live-console`` (``live.sh console``): the generated WebLab started by its scripts as two
processes on free loopback ports, and the console attached to them over Pyro5 (their observer and
management interfaces, the application's token), seen in Debian's chromium. The page says it is
attached (Start and Stop disabled, the running seed); it shows both cameras, the trajectory, the
context and the policy firings of the WebLab's process, and the plots with their time axis; a
viewer taking control holds the Navigator of the user's process (its next image waits, no new
frame) and drives the robot; handing back lets the Navigator go on; once the Navigator's run is
over, Ctrl-C stops the console and both processes, with no fault. About 35 s (a 20 s run)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading

import pytest
from weblab_console.serving import free_port

from tests.samples.weblab.test_live_mode import LIVE, alive, cleanup, environment
from tests.samples.weblab_console.test_console_in_a_browser import attr, set_range, text, until
from tests.support.browser import chromium_driver
from tests.support.services import wait_for

READY = re.compile(r"^WebLab console: (http://\S+)$")
# A terminal's foreground job: SIGINT and SIGTERM at their defaults (see test_live_mode).
AS_A_TERMINAL_WOULD = (
    "import os, signal, sys\n"
    "signal.signal(signal.SIGINT, signal.SIG_DFL)\n"
    "signal.signal(signal.SIGTERM, signal.SIG_DFL)\n"
    "os.execvp('sh', ['sh', *sys.argv[1:]])\n"
)


class Live:
    """``live.sh console`` started as a terminal would, its output collected."""

    def __init__(self, env: dict[str, str], port: int) -> None:
        self.process = subprocess.Popen(
            [sys.executable, "-c", AS_A_TERMINAL_WOULD, str(LIVE), "console", "--port", str(port)],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        self.lines: list[str] = []
        self.url: str | None = None
        self.ready = threading.Event()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.append(line)
            found = READY.match(line.rstrip("\n"))
            if found:
                self.url = found[1]
                self.ready.set()
        self.ready.set()  # the end of its output: never ready

    @property
    def output(self) -> str:
        return "".join(self.lines)


@pytest.fixture
def live(weblab_app, tmp_path):
    run = tmp_path / "run"
    env = environment(run, 20)  # the Navigator's run ends after 20 s (then a clean stop)
    started = Live(env, free_port())
    try:
        yield started, run
    finally:
        if started.process.poll() is None:
            os.killpg(started.process.pid, signal.SIGKILL)
            started.process.wait()
        cleanup(env, run)


def test_the_console_attached_to_the_two_processes_shows_and_drives_them(live, tmp_path):
    started, run = live
    assert started.ready.wait(120) and started.url, started.output
    output = started.output
    assert "WebLab console: attached to WebLab: UserSide at 127.0.0.1:" in output
    browser = chromium_driver()
    try:
        browser.get(started.url)
        until(browser, lambda d: "the hands are yours" in text(d, "message"), "the token accepted")
        # Attached: the application's scripts start and stop it, not the page.
        for control in ("start", "stop", "profile", "seed"):
            assert not browser.find_element("id", control).is_enabled(), control
        assert "Attached to the two-process application" in text(browser, "attached")
        until(browser, lambda d: "two processes, seed 0" in text(d, "profile-shown"), "the run")
        assert attr(browser, "seed", "value") == "0"

        for camera in ("onboard", "panoramic"):  # frames replace the placeholders
            until(browser, lambda d, c=camera: int(attr(d, c, "data-frames") or 0) >= 2, camera)
            assert not browser.find_element("id", f"{camera}-waiting").is_displayed()
        until(browser, lambda d: int(attr(d, "map", "data-points") or 0) >= 3, "a trajectory")
        # The generic page around the panel: the architecture, context and policies.
        names = browser.execute_script(
            "return [...document.querySelectorAll('#architecture g.element')]"
            ".map((g) => g.dataset.name)"
        )
        assert {"UserSide", "WebLabSide", "Navigator", "Locomotion", "SpeedLimiting"} <= set(names)
        until(
            browser,
            lambda d: (
                "maxSpeed"
                in d.execute_script(
                    "const box = document.querySelector('.policy-set[data-set=SpeedLimiting]');"
                    "return box ? box.textContent : ''"
                )
            ),
            "SpeedLimiting's firing, which writes Locomotion.maxSpeed",
        )
        browser.get_screenshot_as_file(str(tmp_path / "attached.png"))

        # Take control: the Navigator waits at its next image, the robot goes where we say.
        set_range(browser, "speed", 100)
        set_range(browser, "turn", 0)
        browser.find_element("id", "take").click()
        until(browser, lambda d: attr(d, "map", "data-held") == "1", "the Navigator held")
        assert "The Navigator waits for its next image" in text(browser, "driver")
        frames = int(attr(browser, "onboard", "data-frames"))
        x0 = float(attr(browser, "map", "data-pose").split(",")[0])
        until(
            browser,
            lambda d: abs(float(attr(d, "map", "data-pose").split(",")[0]) - x0) > 60,
            "the robot moving under manual control",
        )
        assert int(attr(browser, "onboard", "data-frames")) <= frames + 1  # one was on its way
        until(browser, lambda d: "manual control taken" in text(d, "events"), "the event")

        browser.find_element("id", "release").click()
        until(browser, lambda d: attr(d, "map", "data-driver") == "navigator", "the hand-back")
        until(
            browser,
            lambda d: int(attr(d, "onboard", "data-frames")) > frames + 1,
            "the Navigator's images again",
        )
        until(browser, lambda d: "handed back" in text(d, "events"), "the hand-back event")
        # The Access component of the WebLab's process decides: another token watches only.
        browser.execute_script("sessionStorage.clear()")
        browser.get(started.url.split("#")[0] + "#token=not-the-token")
        until(browser, lambda d: "does not know this token" in text(d, "message"), "the refusal")
        refusals = [
            e["message"]
            for e in browser.get_log("browser")
            if "Content Security Policy" in e["message"]
        ]
        assert refusals == []
    finally:
        browser.quit()

    # The Navigator's run ends at its time cap; then Ctrl-C stops everything, cleanly.
    user_log = run / "UserSide.log"
    assert wait_for(lambda: "--run Navigator.run() returned" in user_log.read_text(), timeout=90), (
        user_log.read_text()
    )
    os.killpg(started.process.pid, signal.SIGINT)  # what Ctrl-C in a terminal does
    started.process.wait(timeout=60)
    output = started.output
    assert started.process.returncode == 0, output
    assert "live: stopping" in output and "WebLab console stopped" in output
    assert (
        "live: done: the console and both processes stopped, no fault in either process" in output
    )
    pids = re.search(r"live: processes: (\d+) \(UserSide\), (\d+) \(WebLabSide\)", output)
    assert pids and not alive(int(pids[1])) and not alive(int(pids[2]))


def test_attaching_to_an_application_that_does_not_run_is_refused_with_why(weblab_app, tmp_path):
    env = environment(tmp_path / "run", 20)  # free ports nobody serves, on loopback
    env.update(ACORDCS_UserSide_HOST="127.0.0.1", ACORDCS_WebLabSide_HOST="127.0.0.1")
    done = subprocess.run(
        [sys.executable, "-m", "weblab_console", "--attach", str(LIVE.parent / "app")],
        cwd=LIVE.parent,
        env={**env, "PYTHONPATH": f"{LIVE.parent}{os.pathsep}{env['PYTHONPATH']}"},
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2, done.stderr
    assert (
        f"weblab_console: cannot attach to {LIVE.parent / 'app'}: container UserSide does not answer: cannot reach the remote container"
        in done.stderr
    )
    assert "start the application first (make live-console starts it" in done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "run" / "UserSide.pid").exists()
