"""The ventilation sample (two containers, Plant and Office) built with its Fan tagged
``persistent`` and a property added to the Office's Panel, started by its scripts on loopback: a
property of each set through the management interface, both containers killed with SIGKILL, and
started again by their scripts (which take the killed processes' pid files for stale). The Fan's
property is back as it was set, read through the management interface; the Panel (not tagged)
is at the model's initial value. Tampering with the Fan's file while its container is down makes
the next start refuse it (moved aside, said in the log) and the Fan start from the model."""

from __future__ import annotations

import json
import os
import signal
from pathlib import Path

import pytest

from acordcs.runtime.connectors.remote import RemoteConnector
from acordcs.runtime.live.management_server import MANAGE_OBJECT
from tests.support.generator import build
from tests.support.scripts import alive, environment, script, wait_until
from tests.support.services import free_port
from tests.support.toolchain import SAMPLES, replace

TOKEN = "a-token-for-the-ventilation-test-0123"


@pytest.fixture(scope="module")
def app(tmp_path_factory) -> tuple[Path, dict[str, str]]:
    """The built application's bin/ and the scripts' environment; stopped at the end."""
    root = tmp_path_factory.mktemp("persistent")
    text = (SAMPLES / "papyrus" / "ventilation.acord").read_text()
    text = replace(
        text, 'component Fan id "_Fan" {', 'component Fan id "_Fan" (persistent = true) {'
    )
    text = replace(
        text,
        "(language = python) {\n",
        "(language = python) {\n    attribute brightness: int = 50\n",
    )
    model = root / "ventilation.acord"
    model.write_text(text)
    result = build(model, root / "out", "-t", "python,shell")
    assert result.code == 0, result.both
    run = root / "run"
    run.mkdir(mode=0o700)
    env = environment(
        run,
        ACORDCS_TOKEN=TOKEN,
        ACORDCS_Plant_HOST="127.0.0.1",
        ACORDCS_Office_HOST="127.0.0.1",
        ACORDCS_Plant_PORT=str(free_port()),
        ACORDCS_Office_PORT=str(free_port()),
    )
    bin_ = root / "out" / "bin"
    yield bin_, env
    script(bin_, "stop-all", env)


def ask(env: dict[str, str], container: str, method: str, *args: object) -> object:
    uri = f"PYRO:{MANAGE_OBJECT.format(container)}@127.0.0.1:{env[f'ACORDCS_{container}_PORT']}"
    connector = RemoteConnector(timeout=5.0, token=TOKEN)
    try:
        return connector.request(uri, method, *args, where="test")
    finally:
        connector.close()


def start(bin_: Path, env: dict[str, str], *names: str) -> None:
    for name in names:  # each start script returns once its container serves
        started = script(bin_, f"{name}-start", env)
        assert started.returncode == 0, started.stdout + started.stderr


def kill(env: dict[str, str], *names: str) -> None:
    for name in names:
        pid = int((Path(env["ACORDCS_RUN_DIR"]) / f"{name}.pid").read_text())
        os.kill(pid, signal.SIGKILL)
        wait_until(lambda pid=pid: not alive(pid), f"{name} (pid {pid}) gone")


def state_on_disk(env: dict[str, str]) -> dict:
    try:
        doc = json.loads((Path(env["ACORDCS_RUN_DIR"]) / "Fan.state.json").read_text())
    except (FileNotFoundError, json.JSONDecodeError):
        return {}
    return doc["state"]["properties"]


def test_the_persistent_fan_is_restored_and_the_panel_is_not(app):
    bin_, env = app
    start(bin_, env, "Office", "Plant")
    ask(env, "Plant", "set_property", "Fan", "filterHours", 321)
    ask(env, "Office", "set_property", "Panel", "brightness", 80)
    assert ask(env, "Office", "properties", ["Panel"]) == {"Panel": {"brightness": 80}}
    # what the container wrote: on disk a moment after the change (what a crash then keeps)
    wait_until(lambda: state_on_disk(env).get("filterHours") == 321, "the Fan's state written", 10)
    kill(env, "Plant", "Office")
    start(bin_, env, "Office", "Plant")
    assert ask(env, "Plant", "properties", ["Fan"]) == {"Fan": {"speed": 20.0, "filterHours": 321}}
    assert ask(env, "Office", "properties", ["Panel"]) == {"Panel": {"brightness": 50}}
    log = (Path(env["ACORDCS_RUN_DIR"]) / "Plant.log").read_text()
    assert f"Fan: state restored from {env['ACORDCS_RUN_DIR']}/Fan.state.json (2 properties" in log


def test_a_file_tampered_with_while_the_container_is_down_is_refused(app):
    bin_, env = app
    run = Path(env["ACORDCS_RUN_DIR"])
    script(bin_, "Plant-stop", env)
    path = run / "Fan.state.json"
    doc = json.loads(path.read_text())
    doc["state"]["properties"]["filterHours"] = 9999
    path.write_text(json.dumps(doc))
    start(bin_, env, "Plant")
    assert ask(env, "Plant", "properties", ["Fan"]) == {"Fan": {"speed": 20.0, "filterHours": 0}}
    (aside,) = run.glob("Fan.state.json.refused-*")
    assert json.loads(aside.read_text())["state"]["properties"]["filterHours"] == 9999
    log = (run / "Plant.log").read_text()
    assert f"warning: Fan: state file {path} refused: its signature does not match" in log
    assert f"moved aside to {aside};" in log
