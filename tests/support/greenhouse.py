"""The tutorial's greenhouse (one container, House: a Sensor polled by the Climate monitor at 1 Hz,
a Vent the Ventilation policy set opens) as the tests of ``acordcs-gen update`` and of the start
scripts run it: built into a directory, started by its scripts on loopback in real time, updated
with ``acordcs-gen update`` in this process under the scripts' environment, asked what it runs
through its management interface."""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from tests.support.generator import build
from tests.support.toolchain import ROOT, CliResult, update_under

GREENHOUSE = ROOT / "samples" / "tutorial" / "greenhouse.uml"
PACKAGE = "greenhouse_app"

# The sensor counts its readings (its state, kept across a replacement) and reads BASE + count.
SENSOR = '''"""The greenhouse's sensor, for the tests: reading n gives BASE + n."""

from __future__ import annotations

from greenhouse_app.base.Sensor import SensorBase

BASE = 0.0


class Sensor(SensorBase):
    state_fields = ("count",)
    count = 0  # not set in on_start, which runs again after a replacement restored the state

    def readTemperature(self) -> float:
        self.count += 1
        return BASE + self.count
'''


def sensor(base: float) -> str:
    """The sensor's code reading ``base`` + its count."""
    return SENSOR.replace("BASE = 0.0", f"BASE = {base!r}")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def environment(run: Path, port: int, **more: str) -> dict[str, str]:
    """The scripts' environment: this process's without ACORDCS_ settings, real time, the House
    on loopback at ``port``, the run directory ``run``."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("ACORDCS_")}
    return {
        **env,
        "PYTHONPATH": str(ROOT / "src"),
        "ACORDCS_RUN_DIR": str(run),
        "ACORDCS_CLOCK": "real",
        "ACORDCS_House_HOST": "127.0.0.1",
        "ACORDCS_House_PORT": str(port),
        "ACORDCS_STOP_TIMEOUT": "5",
        **more,
    }


def built(root: Path, *targets: str, code: str | None = SENSOR) -> tuple[Path, Path]:
    """The greenhouse's model copied into ``root`` and built into ``root/app`` (``targets``:
    ``-t`` options, default all), the sensor's code ``code`` written (None: the build's stub);
    (model, app)."""
    model = root / "greenhouse.uml"
    shutil.copy(GREENHOUSE, model)
    app = root / "app"
    done = build(model, app, *[a for t in targets for a in ("-t", t)])
    assert done.code == 0, done.both
    if code is not None:
        (app / PACKAGE / "components" / "Sensor.py").write_text(code, encoding="utf-8")
    return model, app


def script(app: Path, name: str, env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run(["sh", str(app / "bin" / name)], env=env, capture_output=True,
                          text=True, timeout=120, check=False)  # fmt: skip


@contextlib.contextmanager
def running(app: Path, **more: str) -> Iterator[dict[str, str]]:
    """The greenhouse of ``app`` started by ``bin/start-all`` (a run directory beside it, a free
    port); its environment. Stopped by ``bin/stop-all`` at the end."""
    run = app.parent / "run"
    run.mkdir(mode=0o700, exist_ok=True)
    env = environment(run, free_port(), **more)
    started = script(app, "start-all", env)
    try:
        assert started.returncode == 0, started.stdout + started.stderr
        yield env
    finally:
        script(app, "stop-all", env)


def update(env: dict[str, str], *args: str) -> CliResult:
    """``acordcs-gen update ARGS...`` in this process, under ``env``."""
    return update_under(env, *args)


def manage(env: dict[str, str], method: str, *args: Any) -> Any:
    """Call ``method`` of the House's management interface with the application's token."""
    from acordcs.runtime.connectors.remote import RemoteConnector

    token = (Path(env["ACORDCS_RUN_DIR"]) / "token").read_text().strip()
    uri = f"PYRO:acordcs.manage.House@127.0.0.1:{env['ACORDCS_House_PORT']}"
    connector = RemoteConnector(timeout=10, token=token)
    try:
        return connector.request(uri, method, *args, where="House", what=method)
    finally:
        connector.close()


def temperature(env: dict[str, str]) -> float:
    """The Climate monitor's temperature now: the sensor's last reading."""
    return float(manage(env, "properties", ["Climate"])["Climate"]["temperature"])
