"""How a model operation's ``out`` and ``inout`` parameters map to Python: the arguments are the
``in`` and ``inout`` parameters in order; the result of an operation with ``out`` or ``inout``
parameters is the tuple (return value, then each out/inout parameter's final value in order), the
return value None when the operation returns nothing. Assembly checks the results of such calls."""

from __future__ import annotations

import inspect
from typing import ClassVar

from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.operations import out_parameters, signature
from tests.support.descriptors import application, component, container, op, ref

FIND = op(
    "find",
    ("frame", "Image", "in"),
    ("x", "double", "out"),
    ("y", "double", "inout"),
    returns="bool",
)
MEASURE = op("measure", ("value", "double", "out"))
GRAB = op("grab", returns="Image")


def vision(cls=None):
    app = application(
        "Lab",
        containers=(container("lab", ref("component", "Vision")),),
        components=(component("Vision", operations=(FIND, MEASURE, GRAB)),),
    )
    return assemble(app, factories={"Vision": cls} if cls else None, clock=VirtualClock())


def test_the_arguments_are_the_in_and_inout_parameters():
    assert list(signature(FIND).parameters) == ["frame", "y"]
    assert out_parameters(FIND) == ("x", "y")
    assert out_parameters(GRAB) == ()
    with vision() as app:
        generic = type(app.container().find("Vision").instance)
        assert list(inspect.signature(generic.find).parameters) == ["self", "frame", "y"]
        assert "(return value, x, y)" in generic.find.__doc__


class Vision(CtxComponent):
    properties: ClassVar[dict[str, object]] = {}

    def find(self, frame: str, y: float) -> tuple[bool, float, float]:
        return True, 10.0, y + 1.0

    def measure(self) -> tuple[None, float]:
        return None, 4.5

    def grab(self) -> str:
        return "image"


def test_results_are_the_return_value_then_the_out_values():
    with vision(Vision) as app:
        lab = app.container()
        ref_ = lab.find("Vision")
        assert ref_.find("img", y=2.0) == (True, 10.0, 3.0)
        assert ref_.measure() == (None, 4.5)
        assert ref_.grab() == "image"  # no out parameter: the return value itself
        assert lab.faults.counts["total"] == 0


class SloppyVision(Vision):
    def find(self, frame: str, y: float) -> bool:  # forgets x and y
        return True


def test_a_result_that_does_not_map_the_out_parameters_is_a_fault():
    with vision(SloppyVision) as app:
        lab = app.container()
        assert lab.find("Vision").find("img", 2.0) is True  # the caller gets what was returned
        (fault,) = lab.faults.of_kind("interceptor")
        assert fault.where == "out-parameters:Vision"
        assert "Vision.find() returned True" in fault.error
        assert "(return value, x, y)" in fault.error
