"""Building running containers from an ACORD-CS model (pyecore ``Application``)."""

from __future__ import annotations

from typing import ClassVar

import pytest

from acordcs.metamodel import create, load
from acordcs.runtime.application import build_application, terms_text
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.errors import BindingError, ConfigurationError
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.ports import stream_port
from acordcs.runtime.registry import register_engine, unregister_engine
from tests.support.components import CrispEngine


def lit(enum: str, name: str):
    return load().getEClassifier(enum).getEEnumLiteral(name)


def attribute(name: str, type_: str, default: str | None = None, **var):
    variable = None
    if var:
        terms = [
            create("LinguisticTerm", name=n, shape=lit("MembershipShape", s), parameters=p)
            for n, s, p in var.pop("terms", [])
        ]
        variable = create("CtxVariable", terms=terms, **var)
    return create("Attribute", name=name, type=type_, defaultValue=default, variable=variable)


def weblab_model(engine: str = "clips"):
    video_out = create(
        "CtxPort", name="video", kind=lit("PortKind", "stream"), role=lit("PortRole", "provided")
    )
    video_in = create(
        "CtxPort", name="video", kind=lit("PortKind", "stream"), role=lit("PortRole", "required")
    )
    camera = create(
        "CtxComponent", name="Camera", attributes=[attribute("fps", "int", "12")], ports=[video_out]
    )
    console = create("CtxComponent", name="Console", ports=[video_in])
    link = create(
        "CtxPortConnection",
        name="panorama",
        connector=lit("ConnectorKind", "shaped"),
        provided=video_out,
        required=video_in,
        attributes=[
            attribute("latency", "double", "0.05"),
            attribute("bandwidth", "double", "2000000"),
        ],
    )
    usage = create(
        "CtxMonitor", name="Usage", frequency=1.0, attributes=[attribute("numUsers", "int", "0")]
    )
    rules = [
        create("Rule", label="crowded", text="if Usage.numUsers > 2 then Camera.fps = 4"),
        create("Rule", text="if Usage.numUsers <= 2 then Camera.fps = 12"),
    ]
    policy = create("CtxPolicy", name="bandwidth", rules=rules)
    pset = create(
        "CtxPolicySet",
        name="BandwidthLimiting",
        engine=lit("EngineKind", engine),
        trigger=lit("PolicyTrigger", "event"),
        adapts=[camera],
        policies=[policy],
    )
    usage.feeds.append(pset)
    lab = create(
        "CtxContainer",
        name="weblab",
        components=[camera, console],
        monitors=[usage],
        policySets=[pset],
    )
    return create(
        "Application",
        name="WebLab",
        containers=[lab],
        components=[camera, console],
        monitors=[usage],
        policySets=[pset],
        connections=[link],
    )


class Camera(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"fps": 12}
    ports = (stream_port("video"),)


class UsagePoll(Monitor):
    def acquire(self):
        return {"numUsers": min(self.ticks, 5)}


@pytest.fixture
def crisp_as_clips():
    # The model's engine tag is 'clips'; the registry lets the test bind it to its own crisp engine.
    register_engine("clips", CrispEngine)
    yield
    unregister_engine("clips")


def test_build_from_model_runs_policies_monitors_and_connections(crisp_as_clips):
    app = build_application(
        weblab_model(),
        factories={"Camera": Camera},
        monitors={"Usage": UsagePoll},
        clock=VirtualClock(seed=1),
    )
    with app:
        lab = app.container("weblab")
        assert [r.name for r in lab.components()] == ["Camera", "Console"]
        assert type(lab.find("Camera").instance) is Camera
        assert (
            lab.find("Console").instance.port("video").kind == "stream"
        )  # generic, from the model
        assert lab.connection("panorama").connector.kind == "shaped"
        assert lab.get_property("panorama", "latency") == 0.05
        ps = lab.policy_set("BandwidthLimiting")
        assert ps.inputs["Usage.numUsers"] == ("Usage", "numUsers")
        app.clock.run_for(2.5)
        assert lab.get_property("Camera", "fps") == 12
        app.clock.run_for(1.0)  # third tick: three users
        assert lab.get_property("Camera", "fps") == 4


def test_unknown_container_and_missing_remote_end_are_reported(crisp_as_clips):
    model = weblab_model()
    with (
        build_application(model, clock=VirtualClock()) as app,
        pytest.raises(BindingError, match="no container 'nowhere' here"),
    ):
        app.container("nowhere")
    console_host = create("CtxContainer", name="home", components=[model.components[1]])
    model.containers[0].components.remove(model.components[1])
    model.containers.append(console_host)
    with pytest.raises(BindingError, match=r"Console.video is in container 'home', not built here"):
        build_application(model, only=["weblab"], clock=VirtualClock())


def test_terms_are_written_fcl_style():
    attr = attribute(
        "speed",
        "double",
        rangeMin=0.0,
        rangeMax=200.0,
        terms=[
            ("slow", "trapezoid", [0.0, 0.0, 40.0, 80.0]),
            ("fast", "triangle", [60.0, 200.0, 200.0]),
        ],
    )
    assert terms_text(attr.variable) == "slow := trape 0 0 40 80; fast := trian 60 200 200"


def test_bad_model_settings_are_clear_errors(crisp_as_clips):
    model = weblab_model()
    model.components[0].attributes[0].defaultValue = "twelve"
    with pytest.raises(
        ConfigurationError, match=r"attribute Camera\.fps: default 'twelve' is not of type 'int'"
    ):
        build_application(model, clock=VirtualClock())
    model = weblab_model()
    model.policySets[0].trigger = lit("PolicyTrigger", "periodic")
    with pytest.raises(ConfigurationError, match="a periodic set needs a frequency > 0 Hz"):
        build_application(model, clock=VirtualClock())
