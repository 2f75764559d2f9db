"""A port's properties in the model are properties of the running port (rule variables such as
``Camera.video.format``); a generic component's stream port also takes its rate from the model, while
a factory's class keeps its own rate, capacity and overflow."""

from __future__ import annotations

from typing import ClassVar

from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.ports import stream_port
from tests.support.descriptors import application, component, container, port, prop, ref


def camera_app():
    video = port("video", "stream", "provided", prop("format", "mjpeg"), prop("rate", 0.0))
    return application(
        "Lab",
        containers=(container("lab", ref("component", "Camera")),),
        components=(component("Camera", ports=(video,)),),
    )


def test_model_port_properties_are_port_properties():
    with assemble(camera_app(), clock=VirtualClock()) as app:
        lab = app.container()
        assert lab.get_property("Camera.video", "format") == "mjpeg"
        assert lab.get_property("Camera.video", "rate") == 0.0
        lab.set_property("Camera.video", "format", "h264")
        assert lab.get_property("Camera.video", "format") == "h264"


class Camera(CtxComponent):
    properties: ClassVar[dict[str, object]] = {}
    ports = (stream_port("video", rate=12.0, source="grab"),)

    def grab(self) -> int:
        return 1


def test_a_factory_class_keeps_its_port_settings():
    with assemble(camera_app(), factories={"Camera": Camera}, clock=VirtualClock()) as app:
        lab = app.container()
        assert lab.get_property("Camera.video", "rate") == 12.0
        assert lab.get_property("Camera.video", "format") == "mjpeg"
