"""A container's management takes, beside a new descriptor, the components and monitors whose code
(the user's file) changed: each is ``~ code of component C`` in its part, applied by replacing the
component by its class read afresh, keeping its state (``state_fields``, properties, handles), and
a monitor by a new one keeping its attributes' values, also when the descriptor is the one it
runs. It reports the files it loaded (``status()["code"]``, from its classes' ``code``) and, after
the update, the new ones; a name it does not host is refused, nothing applied; a part that fails
is rolled back with the old class running. The generated package's classes give the digests of
the user's files (``PackageClasses.code``)."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from acordcs.descriptor import to_xml
from acordcs.runtime.acquisition import InterceptingMonitor
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management import Management, digest
from acordcs.runtime.live.reloading import PackageClasses
from tests.support.descriptors import application, component, container, monitor, op, prop, ref
from tests.support.generator import build
from tests.support.toolchain import WEBLAB

APP = application(
    "Plant",
    containers=(
        container("greenhouse", ref("component", "Pump"), ref("monitor", "Soil")),
        container("office", ref("component", "Desk")),
    ),
    components=(
        component("Pump", properties=(prop("litres", 0),), operations=(op("water"),)),
        component("Desk"),
    ),
    monitors=(monitor("Soil", prop("moisture", 0.5)),),
)


class Pump(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"litres": 0}
    state_fields = ("strokes",)
    strokes = 0

    def water(self) -> str:
        self.strokes += 1
        return f"old {self.strokes}"


class NewPump(Pump):
    def water(self) -> str:
        self.strokes += 1
        return f"new {self.strokes}"


class Failing(Pump):
    def __init__(self) -> None:
        raise RuntimeError("the new driver is missing")


class NewSoil(InterceptingMonitor):
    pass


@dataclass
class Files(GivenClasses):
    """Classes given as they are, with the digests of made-up files."""

    files: dict[str, dict[str, str]] = field(default_factory=dict)

    def code(self, names):
        return {n: self.files[n] for n in names if n in self.files}


def record(name: str, text: str) -> dict[str, str]:
    return {"kind": "component", "file": f"plant_app/components/{name}.py", "sha256": text}


def management(run, classes) -> Management:
    return Management(
        run, "greenhouse", to_xml(APP), classes=classes, code={"Pump": record("Pump", "v1")}
    )


def test_a_component_whose_code_changed_is_replaced_keeping_its_state():
    with assemble(APP, factories={"Pump": Pump}, clock=VirtualClock(), only=["greenhouse"]) as run:
        house = run.container("greenhouse")
        pump = house.find("Pump")
        assert pump.water() == "old 1"
        house.set_property("Pump", "litres", 12)
        classes = Files(factories={"Pump": NewPump}, files={"Pump": record("Pump", "v2")})
        managed = management(run, classes)
        assert managed.status()["code"] == {"Pump": record("Pump", "v1")}
        reply = managed.apply(to_xml(APP).decode(), managed.digest, {}, False, ["Pump"])
        assert reply["status"] == "applied", reply
        assert reply["applied"] == ["~ code of component Pump"]
        assert reply["digest"] == digest(to_xml(APP))  # the descriptor it runs, as before
        assert type(house.instance("Pump")) is NewPump
        assert pump.alive and pump.water() == "new 2"  # the handle follows; the count is kept
        assert house.get_property("Pump", "litres") == 12
        assert managed.status()["code"] == {"Pump": record("Pump", "v2")}


def test_a_monitor_whose_code_changed_keeps_its_attributes_values():
    with assemble(APP, factories={"Pump": Pump}, clock=VirtualClock(), only=["greenhouse"]) as run:
        house = run.container("greenhouse")
        house.monitor("Soil").update(moisture=0.8)
        managed = management(
            run, GivenClasses(factories={"Pump": Pump}, monitors={"Soil": NewSoil})
        )
        reply = managed.apply(to_xml(APP).decode(), managed.digest, {}, False, ["Soil"])
        assert reply["status"] == "applied" and reply["applied"] == ["~ code of monitor Soil"]
        assert isinstance(house.monitor("Soil"), NewSoil)
        assert house.monitor("Soil").attributes["moisture"] == 0.8


def test_a_name_it_does_not_host_is_refused_and_nothing_applied():
    with assemble(APP, factories={"Pump": Pump}, clock=VirtualClock(), only=["greenhouse"]) as run:
        managed = management(run, GivenClasses(factories={"Pump": NewPump}))
        for name in ("Desk", "Nothing"):
            reply = managed.apply(to_xml(APP).decode(), managed.digest, {}, False, ["Pump", name])
            assert reply["status"] == "refused"
            assert (
                f"code of '{name}': container 'greenhouse' hosts no component or monitor"
                in (reply["error"])
            )
        assert type(run.container("greenhouse").instance("Pump")) is Pump
        unchanged = managed.apply(to_xml(APP).decode(), managed.digest, {}, False, [])
        assert unchanged["status"] == "unchanged" and unchanged["applied"] == []


def test_code_that_fails_is_rolled_back_with_the_old_class_running():
    with assemble(APP, factories={"Pump": Pump}, clock=VirtualClock(), only=["greenhouse"]) as run:
        house = run.container("greenhouse")
        managed = management(run, GivenClasses(factories={"Pump": Failing}))
        reply = managed.apply(to_xml(APP).decode(), managed.digest, {}, False, ["Pump"])
        assert reply["status"] == "rolled back", reply
        assert (
            "~ code of component Pump: " in reply["error"] and "driver is missing" in reply["error"]
        )
        assert type(house.instance("Pump")) is Pump and house.find("Pump").water() == "old 1"
        assert managed.status()["code"] == {"Pump": record("Pump", "v1")}


def test_the_packages_classes_give_the_digests_of_the_users_files(tmp_path: Path) -> None:
    from tests.support.generator import imported

    assert build(WEBLAB, tmp_path, "-t", "python").code == 0
    with imported(tmp_path, "weblab_app"):
        found = PackageClasses("weblab_app").code(["Vision", "Usage", "Nothing"])
    vision = tmp_path / "weblab_app" / "components" / "Vision.py"
    assert found == {
        "Vision": {
            "kind": "component",
            "file": "weblab_app/components/Vision.py",
            "sha256": hashlib.sha256(vision.read_bytes()).hexdigest(),
        },
        "Usage": {
            "kind": "monitor",
            "file": "weblab_app/monitors/Usage.py",
            "sha256": hashlib.sha256(
                (tmp_path / "weblab_app" / "monitors" / "Usage.py").read_bytes()
            ).hexdigest(),
        },
    }
