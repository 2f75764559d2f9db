"""A component's or monitor's code changed in the user's file is part of ``acordcs-gen update``'s
plan (``~ code of component Sensor``), found by comparing the file with what the running
container loaded (the digests its management interface reports), and applied by replacing the
component by its class read afresh, keeping its state (``save_state``/``restore_state``): the
greenhouse's sensor, which counts its readings, reads from the new base with its count kept.
``--dry-run`` says it and changes nothing; the same update again has nothing to do; code that does
not import is rolled back (the old code runs on, exit 1) and applies once mended."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support.generator import snapshot
from tests.support.greenhouse import (
    PACKAGE,
    built,
    manage,
    running,
    sensor,
    temperature,
    update,
)
from tests.support.scripts import wait_until


@pytest.fixture(scope="module")
def house(tmp_path_factory) -> Iterator[tuple[Path, Path, dict[str, str]]]:
    root = tmp_path_factory.mktemp("code")
    model, app = built(root, "python,shell", code=sensor(0.0))
    with running(app) as env:
        wait_until(lambda: temperature(env) >= 1.0, "the sensor's first reading")
        yield model, app, env


def code_of(app: Path, name: str, folder: str = "components") -> Path:
    return app / PACKAGE / folder / f"{name}.py"


def test_the_container_reports_the_files_it_loaded(house):
    _, app, env = house
    code = manage(env, "status")["code"]
    assert set(code) == {"Sensor", "Vent", "Climate"}
    assert code["Sensor"]["kind"] == "component" and code["Climate"]["kind"] == "monitor"
    assert code["Sensor"]["file"] == f"{PACKAGE}/components/Sensor.py"
    import hashlib

    assert (
        code["Sensor"]["sha256"] == hashlib.sha256(code_of(app, "Sensor").read_bytes()).hexdigest()
    )


def test_changed_code_is_planned_applied_with_its_state_kept_and_then_done(house):
    model, app, env = house
    code_of(app, "Sensor").write_text(sensor(1000.0), encoding="utf-8")
    files = snapshot(app)
    digest = manage(env, "status")["digest"]
    dry = update(env, str(model), "-o", str(app), "--dry-run")
    assert dry.code == 0, dry.both
    assert dry.out.endswith(
        "plan: 1 change\n~ code of component Sensor\ndry run: nothing changed\n"
    ), dry.out
    assert snapshot(app) == files and temperature(env) < 1000.0
    before = temperature(env)
    done = update(env, str(model), "-o", str(app))
    assert done.code == 0, done.both
    assert "plan: 1 change\n~ code of component Sensor\n" in done.out
    assert (
        "House: applied 1 change in " in done.out and f"runs descriptor {digest[:12]}" in done.out
    )
    # The new code reads 1000 + its count, the count kept from before the replacement.
    wait_until(lambda: temperature(env) > 1000.0, "a reading of the new code")
    assert temperature(env) > 1000.0 + before
    log = (Path(env["ACORDCS_RUN_DIR"]) / "House.log").read_text()
    assert "model.updated: ~ code of component Sensor" in log
    again = update(env, str(model), "-o", str(app))
    assert again.code == 0, again.both
    assert "plan: 0 changes (the running application is the model's)" in again.out
    assert f"House: runs descriptor {digest[:12]} already: nothing to do" in again.out


def test_a_monitors_code_is_planned_as_its_own(house):
    model, app, env = house
    path = code_of(app, "Climate", "monitors")
    path.write_text(path.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
    done = update(env, str(model), "-o", str(app))
    assert done.code == 0, done.both
    assert "plan: 1 change\n~ code of monitor Climate\n" in done.out
    assert "House: applied 1 change in " in done.out


def test_code_that_does_not_import_is_rolled_back_and_applies_once_mended(house):
    model, app, env = house
    path = code_of(app, "Sensor")
    good = path.read_text(encoding="utf-8")
    path.write_text(good.replace("def readTemperature", "def readTemperature(("), encoding="utf-8")
    done = update(env, str(model), "-o", str(app))
    assert done.code == 1, done.both
    assert "~ code of component Sensor" in done.out
    assert f"House: failed: loading the classes: {path}:" in done.err
    assert "SyntaxError" in done.err and "fix the syntax there, then update again" in done.err
    assert "as before the update" in done.err
    last = temperature(env)
    wait_until(lambda: temperature(env) > last, "a reading of the code that ran before")
    path.write_text(good.replace("1000.0", "2000.0"), encoding="utf-8")
    mended = update(env, str(model), "-o", str(app))
    assert mended.code == 0, mended.both
    wait_until(lambda: temperature(env) > 2000.0, "a reading of the mended code")
