"""``acordcs-gen update`` builds the targets the application was built with (its manifest,
``.acordcs-manifest.json``, records them), so an application built with ``-t`` is updated without
growing the targets it was not built with; ``-t`` chooses them as ``build``'s does (the same
parsing: repeated or comma-separated; the same errors for an unknown target or stylesheet, exit 2).
The ``python`` target is needed (the containers run its package); a manifest that says nothing is
exit 2, asking for ``-t``. On the greenhouse built with ``-t config,python,shell``."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support.generator import build, snapshot
from tests.support.greenhouse import built, running, update
from tests.support.toolchain import replace

RULE = "if temperature is hot then Vent.opening is wide"
EDITED = "if temperature is hot then Vent.opening is half"


@pytest.fixture(scope="module")
def house(tmp_path_factory) -> Iterator[tuple[Path, Path, dict[str, str]]]:
    root = tmp_path_factory.mktemp("targets")
    model, app = built(root, "config,python", "shell")
    with running(app) as env:
        yield model, app, env


def edited(model: Path, name: str) -> Path:
    path = model.parent / name / model.name
    path.parent.mkdir(exist_ok=True)
    path.write_text(replace(model.read_text(encoding="utf-8"), RULE, EDITED), encoding="utf-8")
    return path


def targets(app: Path) -> list[str]:
    return sorted(json.loads((app / ".acordcs-manifest.json").read_text())["targets"])


def test_the_targets_of_the_manifest_are_built_and_no_other(house):
    model, app, env = house
    assert targets(app) == ["config", "python", "shell"]
    done = update(env, str(edited(model, "hot-half")), "-o", str(app))
    assert done.code == 0, done.both
    assert "~ policy set Ventilation: rule hot: ... is wide -> ... is half" in done.out
    assert "House: applied 1 change in " in done.out
    assert not (app / "java").exists() and not (app / "rules").exists()
    assert targets(app) == ["config", "python", "shell"]


def test_t_chooses_the_targets_as_build_does(house):
    model, app, env = house
    done = update(env, str(model), "-o", str(app), "-t", "python", "-t", "config,shell")
    assert done.code == 0, done.both
    assert "House: applied 1 change in " in done.out  # back to the model's rule
    assert not (app / "java").exists()


@pytest.mark.parametrize(
    "args",
    [("-t", "pyhton"), ("-t", "python,nosuch.xsl"), ("-t", "python", "-t", "bad name.xsl")],
)
def test_a_target_build_refuses_update_refuses_alike(house, tmp_path, args):
    model, app, env = house
    files = snapshot(app)
    refused = build(model, tmp_path / "elsewhere", *args)
    done = update(env, str(model), "-o", str(app), *args)
    assert refused.code == done.code == 2, done.both
    said = refused.err.replace("acordcs-gen build: ", "acordcs-gen update: ")
    assert done.err.endswith(said), (done.err, said)
    assert "Traceback" not in done.err
    assert snapshot(app) == files


def test_without_the_python_target_nothing_is_done(house):
    model, app, env = house
    files = snapshot(app)
    done = update(env, str(model), "-o", str(app), "-t", "config,shell")
    assert done.code == 2
    assert done.err == (
        "acordcs-gen update: targets config, shell: update builds the python target too (the "
        "containers run its package, and read its descriptor.xml): add python to -t\n"
    )
    assert snapshot(app) == files


def test_a_manifest_that_does_not_say_is_exit_2_asking_for_t(house, tmp_path):
    model, app, env = house
    manifest = app / ".acordcs-manifest.json"
    saved = manifest.read_bytes()
    try:
        manifest.write_text("{not json", encoding="utf-8")
        done = update(env, str(model), "-o", str(app))
        assert done.code == 2
        assert "/.acordcs-manifest.json cannot be used (it is not a manifest this version" in (
            done.err
        )
        assert "give them with -t (as to build)" in done.err
        manifest.unlink()
        gone = update(env, str(model), "-o", str(app))
        assert gone.code == 2 and "is missing or lists no target" in gone.err
    finally:
        manifest.write_bytes(saved)


def test_a_stylesheet_of_the_manifest_asks_for_its_path(house):
    model, app, env = house
    manifest = app / ".acordcs-manifest.json"
    saved = manifest.read_bytes()
    try:
        data = json.loads(saved)
        data["targets"]["mine.xsl"] = dict(data["targets"]["config"])
        manifest.write_text(json.dumps(data), encoding="utf-8")
        done = update(env, str(model), "-o", str(app))
        assert done.code == 2
        assert (
            "the application was built with your stylesheet mine.xsl (" in done.err
            and "give every target with -t, a stylesheet by its path (-t "
            "config,python,shell,path/to/your.xsl)"
            in done.err
        )
    finally:
        manifest.write_bytes(saved)
