"""A component no factory implements gets the model's operations with their parameters: rules
calling them bind, and a call says which component and operation lack code and what to do."""

from __future__ import annotations

import inspect

import pytest

from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.errors import (
    ComponentError,
    ConfigurationError,
    OperationNotImplementedError,
    RuntimeFailure,
)
from tests.support.descriptors import (
    application,
    component,
    container,
    monitor,
    op,
    policy_set,
    prop,
    ref,
)

RECOVERY = component(
    "Recovery",
    properties=(prop("retries", 0),),
    operations=(
        op("recover"),
        op("move", ("speed", "double", "in"), ("turn", "double", "in"), returns="bool"),
    ),
)


def recovering(*components):
    hosted = [ref("component", c.name) for c in components]
    return application(
        "Robot",
        containers=(
            container("lab", *hosted, ref("monitor", "Control"), ref("policy-set", "Recovering")),
        ),
        components=components,
        monitors=(monitor("Control", prop("speed", 1.0), feeds=("Recovering",)),),
        policy_sets=(
            policy_set(
                "Recovering",
                {"rules": ["retry: if Control.speed == 0 then Recovery.recover()"]},
                engine="clips",
                adapts=(ref("component", "Recovery"),),
            ),
        ),
    )


def test_crisp_rules_calling_an_operation_of_a_generic_component_bind():
    with assemble(recovering(RECOVERY), clock=VirtualClock()) as app:
        lab = app.container("lab")
        assert lab.policy_set("Recovering").operations == {
            "Recovery.recover": ("Recovery", "recover")
        }
        lab.find("Recovery")  # generic: no factory given
        # Firing calls the operation: there is no code for it, a fault that says so.
        lab.monitor("Control").update(speed=0.0)
        (fault,) = lab.faults.of_kind("component")
        assert fault.where == "Recovery.recover"
        assert "component 'Recovery' has no code for operation recover()" in fault.error


def test_calling_a_model_operation_without_code_says_what_to_do():
    with assemble(recovering(RECOVERY), clock=VirtualClock()) as app:
        recovery = app.container("lab").find("Recovery")
        with pytest.raises(OperationNotImplementedError) as info:
            recovery.move(10.0, 5.0)
        err = info.value
        assert isinstance(err, NotImplementedError) and isinstance(err, RuntimeFailure)
        assert "component 'Recovery' has no code for operation move(speed, turn)" in str(err)
        assert "factories={'Recovery': YourClass}" in err.hint
        assert err.where == "container 'lab'"


def test_generic_operations_take_the_model_parameters():
    with assemble(recovering(RECOVERY), clock=VirtualClock()) as app:
        recovery = app.container("lab").find("Recovery")
        cls = type(recovery.instance)
        assert list(inspect.signature(cls.move).parameters) == ["self", "speed", "turn"]
        assert cls.operation_names() == frozenset({"recover", "move"})
        with pytest.raises(ComponentError, match=r"move\(\).*missing a required argument: 'turn'"):
            recovery.move(10.0)


def test_an_operation_named_like_the_component_api_is_refused():
    clash = component("Recovery", operations=(op("set", ("value", "int", "in")),))
    with pytest.raises(ConfigurationError, match=r"operation 'set' of component 'Recovery'"):
        assemble(recovering(clash), clock=VirtualClock())


def test_a_parameter_python_cannot_take_is_refused():
    odd = component("Recovery", operations=(op("go", ("from", "string", "in")),))
    with pytest.raises(ConfigurationError, match=r"parameter 'from' of operation M::go"):
        assemble(recovering(odd), clock=VirtualClock())
