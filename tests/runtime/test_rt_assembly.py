"""Assembling running containers from an application descriptor (``acordcs.runtime.assembly``)."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from typing import ClassVar

import pytest

from acordcs.engines.engine_registry import register_engine, unregister_engine
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.errors import BindingError, ConfigurationError
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.ports import stream_port
from tests.support.components import CrispEngine
from tests.support.descriptors import (
    application,
    component,
    connection,
    container,
    monitor,
    policy_set,
    port,
    prop,
    ref,
    variable,
)


def weblab(engine: str = "clips", trigger: str = "event", lab: tuple = ()):
    """A camera streaming to a console over a shaped link; a periodic monitor counts users; a
    policy set lowers the camera's frame rate when the lab is crowded."""
    hosted = (
        ref("component", "Camera"),
        ref("component", "Console"),
        ref("monitor", "Usage"),
        ref("policy-set", "BandwidthLimiting"),
    )
    return application(
        "WebLab",
        containers=(container("weblab", *hosted, properties=lab),),
        components=(
            component("Camera", properties=(prop("fps", 12),), ports=(port("video", "stream"),)),
            component("Console", ports=(port("video", "stream", "required"),)),
        ),
        connections=(
            connection(
                "panorama",
                "Console.video",
                "Camera.video",
                "shaped",
                prop("latency", 0.05),
                prop("bandwidth", 2e6),
            ),
        ),
        monitors=(
            monitor("Usage", prop("numUsers", 0), frequency=1.0, feeds=("BandwidthLimiting",)),
        ),
        policy_sets=(
            policy_set(
                "BandwidthLimiting",
                {
                    "bandwidth": [
                        "crowded: if Usage.numUsers > 2 then Camera.fps = 4",
                        "if Usage.numUsers <= 2 then Camera.fps = 12",
                    ]
                },
                engine=engine,
                trigger=trigger,
                adapts=(ref("component", "Camera"),),
            ),
        ),
    )


class Camera(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"fps": 12}
    ports = (stream_port("video"),)


class UsagePoll(Monitor):
    def acquire(self):
        return {"numUsers": min(self.ticks, 5)}


@pytest.fixture
def crisp_as_clips():
    # The descriptor's engine is 'clips'; the registry lets the test bind it to its own crisp engine.
    register_engine("clips", CrispEngine)
    yield
    unregister_engine("clips")


def test_assembled_application_runs_policies_monitors_and_connections(crisp_as_clips):
    app = assemble(
        weblab(lab=(prop("site", "Brazil"),)),
        factories={"Camera": Camera},
        monitors={"Usage": UsagePoll},
        clock=VirtualClock(seed=1),
    )
    with app:
        lab = app.container("weblab")
        assert app.container() is lab
        assert lab.get_property("weblab", "site") == "Brazil"
        assert [r.name for r in lab.components()] == ["Camera", "Console"]
        assert type(lab.find("Camera").instance) is Camera
        console = lab.find("Console").instance  # generic, from the descriptor
        assert console.port("video").kind == "stream"
        assert console.port("video").role == "required"
        assert lab.connection("panorama").connector.kind == "shaped"
        assert lab.get_property("panorama", "latency") == 0.05
        ps = lab.policy_set("BandwidthLimiting")
        assert ps.inputs["Usage.numUsers"] == ("Usage", "numUsers")
        assert ps.fed_by == ("Usage",)
        app.clock.run_for(2.5)
        assert lab.get_property("Camera", "fps") == 12
        app.clock.run_for(1.0)  # third tick: three users
        assert lab.get_property("Camera", "fps") == 4


def test_unknown_container_and_missing_remote_end_are_reported(crisp_as_clips):
    with (
        assemble(weblab(), clock=VirtualClock()) as app,
        pytest.raises(BindingError, match="no container 'nowhere' here"),
    ):
        app.container("nowhere")
    split = weblab()
    (lab,) = split.containers
    lab = replace(lab, hosts=tuple(r for r in lab.hosts if r.name != "Console"))
    split = replace(split, containers=(container("home", ref("component", "Console")), lab))
    with pytest.raises(BindingError, match=r"Console.video is in container 'home', not built here"):
        assemble(split, only=["weblab"], clock=VirtualClock())
    with pytest.raises(BindingError, match=r"no container 'lab' \(containers: home, weblab\)"):
        assemble(split, only=["lab"], clock=VirtualClock())


PARTS = ("containers", "components", "connections", "monitors")


def test_policy_sets_get_the_linguistic_variables_of_their_scope():
    speed = variable("Camera", "fps", 0.0, 30.0, slow="trapezoid 0 0 5 10", fast="triangle 8 30 30")
    users = variable(
        "Usage", "numUsers", 0.0, 10.0, few="trapezoid 0 0 1 3", many="trapezoid 1 3 10 10"
    )
    base = weblab()
    (ps,) = base.policy_sets
    rules = policy_set("x", {"fps": ["if numUsers is many then Camera.fps is slow"]}).policies
    fuzzy = replace(ps, engine="fuzzy", policies=rules, variables=(speed, users), bound=())
    app = application(base.name, **{k: getattr(base, k) for k in PARTS}, policy_sets=(fuzzy,))
    with assemble(app, clock=VirtualClock()) as run:
        ps = run.container().policy_set("BandwidthLimiting")
        assert ps.engine.variables["Camera.fps"].terms["fast"].fcl() == "trian 8 30 30"
        assert ps.engine.variables["Camera.fps"].hi == 30.0
        assert [*ps.engine.variables["Usage.numUsers"].terms] == ["few", "many"]
        assert ps.inputs == {"Usage.numUsers": ("Usage", "numUsers")}
        assert ps.outputs == {"Camera.fps": ("Camera", "fps")}


def test_bad_settings_are_clear_errors(crisp_as_clips):
    with pytest.raises(ConfigurationError, match="a periodic set needs a frequency > 0 Hz"):
        assemble(weblab(trigger="periodic"), clock=VirtualClock())


def test_the_runtime_reads_the_descriptor_without_loading_the_toolchain():
    # The descriptor is the boundary: a deployed application runs without the model readers.
    code = (
        "import sys, acordcs.runtime.api, acordcs.runtime.assembly;"
        "print(sorted(m for m in sys.modules if m.startswith(('acordcs.model', 'acordcs.xmi', "
        "'acordcs.descriptor', 'pyecore', 'lxml'))))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
