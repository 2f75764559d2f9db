"""The WebLab simulator's tests: ``samples/weblab`` on sys.path (for ``weblab_sim``), and the
application generated from ``weblab.xmi`` built into ``samples/weblab/app`` (where its component
code lives) once per session, as ``make demo`` builds it; a no-op when it is up to date."""

from __future__ import annotations

import contextlib
import io
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from acordcs.cli import main
from tests.support.toolchain import WEBLAB

SAMPLE_DIR = WEBLAB.parent
APP_DIR = SAMPLE_DIR / "app"
if str(SAMPLE_DIR) not in sys.path:
    sys.path.insert(0, str(SAMPLE_DIR))


@pytest.fixture(scope="session")
def weblab_app() -> None:
    """The generated application, built (or found up to date) in samples/weblab/app."""
    assert main(["build", str(WEBLAB), "-o", str(APP_DIR)]) == 0


class DemoInBackground:
    """The experiment as ``make demo`` runs it (its default seeds, every condition and profile), started as
    soon as collection shows a test needs it: it takes minutes on its own processes, and the rest
    of the suite runs on one core meanwhile, so the suite waits for it once, not on top of it."""

    KEY = pytest.StashKey["DemoInBackground"]()
    NICENESS = 10
    """Below the suite's own processes: the experiment takes the CPU the suite leaves idle (the
    suite is mostly one process on a host of two cores), and the suite's tests that start
    processes and wait for them keep their CPU. Its figures are in simulated time: the same."""

    def __init__(self) -> None:
        with contextlib.redirect_stdout(io.StringIO()) as said:  # collection does not capture
            built = main(["build", "-q", str(WEBLAB), "-o", str(APP_DIR)])
        assert built == 0, said.getvalue()
        self.out = Path(tempfile.mkdtemp(prefix="acordcs-demo-"))
        self.log = (self.out / "stdout.txt").open("w+", encoding="utf-8")
        self.errors = (self.out / "stderr.txt").open("w+", encoding="utf-8")
        nice = shutil.which("nice")
        self.process = subprocess.Popen(
            [
                *([nice, "-n", str(self.NICENESS)] if nice else []),
                sys.executable,
                "-m",
                "weblab_experiment",
                "--out",
                str(self.out / "report"),
                "--no-progress",
            ],
            cwd=SAMPLE_DIR,
            stdout=self.log,
            stderr=self.errors,
            stdin=subprocess.DEVNULL,
            text=True,
        )

    def result(self, timeout: float = 900) -> tuple[int, list[str], str, Path]:
        code = self.process.wait(timeout=timeout)
        self.log.seek(0)
        self.errors.seek(0)
        return code, self.log.read().splitlines(), self.errors.read(), self.out / "report"

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.log.close()
        self.errors.close()
        shutil.rmtree(self.out, ignore_errors=True)


def needs_demo(item: pytest.Item) -> bool:
    return "demo" in getattr(item, "fixturenames", ())


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The tests of the demo's output run last (in their order): the experiment has the whole
    run of the suite to finish in, and the suite waits for it at the end, if at all."""
    items.sort(key=needs_demo)


def pytest_collection_finish(session: pytest.Session) -> None:
    if any(needs_demo(item) for item in session.items):
        session.config.stash[DemoInBackground.KEY] = DemoInBackground()


def pytest_unconfigure(config: pytest.Config) -> None:
    started = config.stash.get(DemoInBackground.KEY, None)
    if started is not None:
        started.close()


@pytest.fixture(scope="session")
def demo(request: pytest.FixtureRequest) -> tuple[list[str], Path]:
    """The demo's output lines (progress bar off: not a terminal) and its report directory."""
    code, lines, errors, out = request.config.stash[DemoInBackground.KEY].result()
    assert code == 0, "\n".join(lines) + errors
    return lines, out
