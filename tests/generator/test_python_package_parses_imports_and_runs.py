"""The ``python`` target's package: every file parses, the package imports, its classes are the
model's (base class from CtxComponent, user class from the base, the registry maps every
component), the same model gives the same bytes, and each container module runs as
``python -m <package>.<container>``."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

from acordcs.generator.targets.python import package_name
from acordcs.runtime.api import CtxComponent, PortSpec
from tests.support.generator import build, imported, python_files
from tests.support.toolchain import ROOT, SMARTROOM, WEBLAB

SAMPLES = {"weblab": (WEBLAB, "WebLab"), "smartroom": (SMARTROOM, "SmartRoom")}


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> dict[str, Path]:
    out = {}
    for key, (model, _) in SAMPLES.items():
        out[key] = tmp_path_factory.mktemp(key)
        result = build(model, out[key], "-t", "python")
        assert result.code == 0, result.both
    return out


def test_package_name_is_derived_safely():
    assert package_name("WebLab") == "weblab_app"
    assert package_name("Smart Room-2") == "smart_room_2_app"
    assert package_name("3D") == "m3d_app"
    assert package_name("os") == "os_app" and package_name("acordcs") == "acordcs_app"
    assert package_name("class") == "class_app"
    for name in ("if", "sys", "x.y", "é"):
        made = package_name(name)
        assert made.isidentifier() and made.isascii() and made not in sys.stdlib_module_names


@pytest.mark.parametrize("key", SAMPLES)
def test_every_generated_file_parses(built, key):
    files = python_files(built[key])
    assert files and all(path.startswith(package_name(SAMPLES[key][1])) for path in files)
    for path, text in files.items():
        ast.parse(text, filename=path)


@pytest.mark.parametrize("key", SAMPLES)
def test_the_package_imports_with_the_models_classes(built, key, weblab, smartroom):
    app = {"weblab": weblab, "smartroom": smartroom}[key]
    package = package_name(app.name)
    with imported(built[key], package) as pkg:
        assert app.name == pkg.APPLICATION
        assert tuple(c.name for c in app.containers) == pkg.CONTAINERS
        assert set(pkg.FACTORIES) == {c.name for c in app.components}
        assert pkg.descriptor() == app
        for comp in app.components:
            cls = pkg.FACTORIES[comp.name]
            assert cls.__name__ == comp.name
            assert cls.__module__ == f"{package}.components.{comp.name}"
            (base,) = cls.__bases__
            assert base.__name__ == f"{comp.name}Base" and base.__bases__ == (CtxComponent,)
            assert cls.properties == {p.name: p.default for p in comp.properties}
            assert [type(v) for v in cls.properties.values()] == [
                type(p.default) for p in comp.properties
            ]
            assert all(isinstance(s, PortSpec) for s in cls.ports)
            assert [(s.name, s.kind, s.role) for s in cls.ports] == [
                (p.name, p.kind, p.role) for p in comp.ports
            ]
            for op in comp.operations:
                method = getattr(base, op.name)
                assert op.name + "(" in method.__doc__
                if op.documentation:
                    assert op.documentation.splitlines()[0] in method.__doc__
            if comp.documentation:
                assert comp.documentation.splitlines()[0] in base.__doc__


def test_the_same_model_gives_the_same_package(built, tmp_path: Path):
    again = build(WEBLAB, tmp_path, "-t", "python")
    assert again.code == 0, again.both
    first = {p: (built["weblab"] / p).read_bytes() for p in python_files(built["weblab"])}
    second = {p: (tmp_path / p).read_bytes() for p in python_files(tmp_path)}
    assert first == second
    assert (built["weblab"] / "weblab_app" / "descriptor.xml").read_bytes() == (
        tmp_path / "weblab_app" / "descriptor.xml"
    ).read_bytes()


def run(directory: Path, *args: str, timeout: float = 60) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(directory), str(ROOT / "src")]))
    return subprocess.run(
        [sys.executable, *args],
        cwd=directory,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def test_a_container_module_has_a_help(built):
    done = run(built["weblab"], "-m", "weblab_app.UserSide", "--help")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("usage: python -m weblab_app.UserSide [-h]")
    for option in ("--clock {virtual,real}", "--serve PORT", "--remote NAME=URI", "--duration"):
        assert option in done.stdout


def test_a_weblab_container_runs_a_few_virtual_seconds(built):
    done = run(
        built["weblab"],
        "-m",
        "weblab_app.WebLabSide",
        "--clock",
        "virtual",
        "--duration",
        "5",
        "--remote",
        "UserSide=PYRO:acordcs.container.UserSide@127.0.0.1:9",
    )
    # The Usage monitor polls Access.countUsers at 1 Hz, which a fresh build has no code for: each
    # of the 5 polls is a fault of the component and of the monitor, isolated, saying what to do;
    # a container that recorded faults exits 3.
    assert done.returncode == 3, done.stderr
    assert done.stdout.splitlines()[-1] == "WebLabSide: stopped at t=5.000 s, faults: 10"
    assert "monitor Usage failed at t=1.000000" in done.stderr
    assert "implement countUsers() in components/Access.py" in done.stderr


def test_a_container_without_the_remotes_it_needs_says_so(built):
    done = run(built["weblab"], "-m", "weblab_app.UserSide")
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert "not built here" in done.stderr
    assert "the other containers: WebLabSide; give the address of each one" in done.stderr
