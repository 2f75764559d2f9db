"""After an operation is renamed in the model (the greenhouse's ``readTemperature``, which the
Climate monitor polls, becomes ``sampleTemperature``) and the user's class still has the old name,
``acordcs-gen update`` says that the operation something calls has no code, in the words a
container says it at start (besides build's G704); ``--strict`` refuses the update (exit 1):
neither the directory nor the container changes. Without it the update applies, and once the
class is mended the warning is gone."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support.generator import snapshot
from tests.support.greenhouse import PACKAGE, built, manage, running, update
from tests.support.toolchain import replace

WARNING = (
    "Sensor.sampleTemperature() has no code, and monitor Climate polls it: implement "
    "sampleTemperature() in class Sensor (each call raises OperationNotImplementedError until "
    "then)"
)


@pytest.fixture(scope="module")
def house(tmp_path_factory) -> Iterator[tuple[Path, Path, dict[str, str]]]:
    root = tmp_path_factory.mktemp("renamed")
    model, app = built(root, "python,shell")
    renamed = root / "renamed" / model.name
    renamed.parent.mkdir()
    text = model.read_text(encoding="utf-8")
    renamed.write_text(replace(text, '"readTemperature"', '"sampleTemperature"', 2), "utf-8")
    with running(app) as env:
        yield renamed, app, env


def test_strict_refuses_and_changes_nothing_then_the_update_applies(house, monkeypatch):
    renamed, app, env = house
    monkeypatch.chdir(app.parent)
    files = snapshot(app)
    digest = manage(env, "status")["digest"]
    source = (app / PACKAGE / "components" / "Sensor.py").read_text(encoding="utf-8")
    line = source.splitlines().index("class Sensor(SensorBase):") + 1
    said = f"app/{PACKAGE}/components/Sensor.py:{line}: warning: {WARNING}"
    strict = update(env, str(renamed), "-o", "app", "--strict")
    assert strict.code == 1, strict.both
    assert (
        "warning: G704 method readTemperature() of class Sensor implements operation" in strict.out
    )
    assert said in strict.out.splitlines()
    assert (
        "~ component Sensor: operation readTemperature(): double -> sampleTemperature(): double"
        in strict.out
    )
    assert strict.err.endswith(
        "acordcs-gen update: --strict: 1 operation that the model calls has no code (listed "
        "above); your classes have drifted from the model (G704, above): nothing changed "
        "(neither the application's directory nor its containers)\n"
    )
    assert snapshot(app) == files and manage(env, "status")["digest"] == digest
    done = update(env, str(renamed), "-o", "app")
    assert done.code == 0, done.both
    assert said in done.out.splitlines()
    assert "House: applied 2 changes in " in done.out
    assert manage(env, "status")["digest"] != digest


def test_the_warning_goes_once_the_class_is_mended(house, monkeypatch):
    renamed, app, env = house
    monkeypatch.chdir(app.parent)
    path = app / PACKAGE / "components" / "Sensor.py"
    path.write_text(
        path.read_text(encoding="utf-8").replace("def readTemperature", "def sampleTemperature"),
        encoding="utf-8",
    )
    done = update(env, str(renamed), "-o", "app", "--strict")
    assert done.code == 0, done.both
    assert "warning" not in done.out
    assert "plan: 1 change\n~ code of component Sensor\n" in done.out
