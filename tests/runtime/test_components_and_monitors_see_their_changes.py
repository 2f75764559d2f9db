"""A component hears its own property changes (``on_property_changed``: who made them does not
matter, a raising hook is the component's fault and the change stands), and a monitor reads its
container's clock as a component does (``monitor.clock``)."""

from __future__ import annotations

from typing import ClassVar

import pytest

from acordcs.engines.engine_registry import Variable
from acordcs.runtime.api import (
    ComponentFactory,
    Container,
    CtxComponent,
    Monitor,
    PolicySet,
    VirtualClock,
)
from acordcs.runtime.errors import ConfigurationError


class Vent(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"opening": 0.0, "other": 0}

    def __init__(self) -> None:
        self.heard: list[tuple[str, object, object, float]] = []

    def on_property_changed(self, name: str, old: object, new: object) -> None:
        self.heard.append((name, old, new, self.clock.now()))
        if new == 99:
            raise RuntimeError("the vent's motor refused")


def test_a_component_hears_changes_made_by_a_policy_set_by_others_and_by_itself():
    c = Container("greenhouse", clock=VirtualClock())
    c.install_factory(ComponentFactory("Vent", Vent))
    c.create("Vent", "vent")
    vent = c.instance("vent")
    heat = Monitor("heat", attributes={"temperature": 20.0})
    c.add_monitor(heat)
    c.add_policy_set(
        PolicySet(
            "ventilation",
            {"p": ["hot: if temperature is hot then vent.opening is wide"]},
            adapts=["vent"],
            fed_by=["heat"],
            variables={
                "heat.temperature": Variable(0, 40, "hot := trape 25 30 40 40"),
                "vent.opening": Variable(0, 100, "wide := trape 60 80 100 100"),
            },
        )
    )
    c.clock.run_until(3.0)
    heat.update(temperature=35.0)  # the policy set opens the vent
    assert vent.heard[-1][0] == "opening" and vent.heard[-1][2] > 60 and vent.heard[-1][3] == 3.0
    c.set_property("vent", "other", 1)  # someone else
    vent.set("other", 2)  # itself
    assert [(n, o, v) for n, o, v, _ in vent.heard[-2:]] == [("other", 0, 1), ("other", 1, 2)]
    before = len(vent.heard)
    vent.set("other", 2)  # no change, no call
    assert len(vent.heard) == before
    c.close()


def test_a_raising_hook_is_a_fault_of_the_component_and_the_change_stands():
    c = Container("greenhouse", clock=VirtualClock())
    c.install_factory(ComponentFactory("Vent", Vent))
    c.create("Vent", "vent")
    c.set_property("vent", "other", 99)
    assert c.get_property("vent", "other") == 99
    (fault,) = c.faults.of_kind("component")
    assert fault.where == "vent.on_property_changed" and "motor refused" in fault.error
    c.close()


def test_a_monitor_reads_its_containers_clock():
    lonely = Monitor("m")
    with pytest.raises(ConfigurationError, match="no clock until it is added"):
        _ = lonely.clock
    c = Container("c", clock=VirtualClock())
    c.add_monitor(lonely)
    c.clock.run_until(1.5)
    assert lonely.clock is c.clock and lonely.clock.now() == 1.5
    c.close()


def test_a_fault_logs_a_traceback_only_for_a_bug_in_hosted_code(caplog):
    c = Container("greenhouse", clock=VirtualClock())
    with caplog.at_level("ERROR", logger="acordcs"):
        c.faults.record("component", "vent.open", ZeroDivisionError("bad arithmetic"), 1.0)
        c.faults.record("component", "vent.close", ConfigurationError("says what to do"), 2.0)
    bug, ours = caplog.records[-2:]
    assert bug.exc_info is not None  # where the user's code broke
    assert ours.exc_info is None and "says what to do" in ours.getMessage()
    c.close()
