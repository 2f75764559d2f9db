"""The component provider with the runtime's real Container: install a factory at run time, use it, remove it."""

from __future__ import annotations

import hashlib
import sys
import zipfile
from pathlib import Path

import pytest

from acordcs.runtime.container import Container
from acordcs.runtime.errors import FactoryError
from acordcs.runtime.repository import (
    ComponentRepository,
    FactoryInstaller,
    FactoryServer,
    RepositoryError,
)

COMPONENT = """
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.ports import PortSpec

from .heuristics import turn_for


class LineFollower(CtxComponent):
    properties = {"offset": 0.0}
    ports = (PortSpec("image", kind="asynchronous", role="required"),)

    def steer(self) -> float:
        return turn_for(self.get("offset"))


def make_factory() -> ComponentFactory:
    return ComponentFactory("weblab.LineFollower", LineFollower)
"""


def build_wheel(directory: Path) -> Path:
    """A pure-Python wheel, written by hand: a wheel is a zip with a .dist-info directory."""
    path = directory / "linefollower-1.2.0-py3-none-any.whl"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("linefollower/__init__.py", "")
        archive.writestr("linefollower/component.py", COMPONENT)
        archive.writestr(
            "linefollower/heuristics.py", "def turn_for(offset):\n    return -0.5 * offset\n"
        )
        archive.writestr(
            "linefollower-1.2.0.dist-info/METADATA", "Metadata-Version: 2.1\nName: linefollower\n"
        )
        archive.writestr(
            "linefollower-1.2.0.dist-info/WHEEL", "Wheel-Version: 1.0\nRoot-Is-Purelib: true\n"
        )
        archive.writestr("linefollower-1.2.0.dist-info/RECORD", "")
    return path


@pytest.fixture
def setup(tmp_path: Path):
    packages = tmp_path / "packages"
    packages.mkdir()
    wheel = build_wheel(packages)
    with FactoryServer(packages) as server:
        repo = ComponentRepository()
        repo.add(
            f'<component name="LineFollower" type="weblab.LineFollower" version="1.2.0">'
            f'<port name="image" kind="asynchronous" role="required"/>'
            f'<factory location="{server.url(wheel.name)}" sha256="{hashlib.sha256(wheel.read_bytes()).hexdigest()}"'
            f' entry="linefollower.component:make_factory"/></component>'
        )
        container = Container("robot")
        yield repo, FactoryInstaller(repo, workdir=tmp_path / "installed"), container
        container.close()


def test_container_installs_uses_and_removes_a_downloaded_factory(setup) -> None:
    repo, installer, container = setup
    (description,) = repo.search("//component[port/@name='image']")
    installed = installer.install(container, description.name)
    assert "weblab.LineFollower" in container.factories()
    follower = container.create("weblab.LineFollower", "lf1", properties={"offset": 4.0})
    assert follower.steer() == -2.0
    assert "linefollower" not in sys.modules
    installer.remove(container, "weblab.LineFollower")
    assert "weblab.LineFollower" not in container.factories()
    assert not installed.directory.exists()
    with pytest.raises(FactoryError):
        container.create("weblab.LineFollower", "lf2")


def test_container_refusing_a_duplicate_leaves_nothing(setup) -> None:
    repo, installer, container = setup
    installer.install(container, "LineFollower")
    other = FactoryInstaller(repo, workdir=installer.workdir / "other")
    with pytest.raises(FactoryError, match="already installed"):
        other.install(container, "LineFollower")
    assert not any((installer.workdir / "other").iterdir())
    with pytest.raises(RepositoryError, match="already installed"):
        installer.install(container, "LineFollower")
    installer.remove(container, "weblab.LineFollower")


def test_described_ports_must_match_the_component(setup, tmp_path: Path) -> None:
    repo, installer, container = setup
    good = repo.get("LineFollower")
    repo.add(
        good.to_xml()
        .replace('name="image"', 'name="camera"')
        .replace('version="1.2.0"', 'version="1.2.1"')
    )
    with pytest.raises(RepositoryError, match="ports"):
        installer.install(container, "LineFollower")
    assert container.factories() == [] and not installer.installed()
