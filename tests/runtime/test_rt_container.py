"""Container: factories, component life cycle, interceptors, events, and fault isolation."""

from __future__ import annotations

import logging

import pytest

from acordcs.runtime import events as ev
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.errors import (
    BindingError,
    CallVetoed,
    ComponentDestroyedError,
    ComponentError,
    ComponentNotFoundError,
    FactoryError,
    PortError,
)
from acordcs.runtime.interceptors import Interceptor, Invocation
from tests.support.components import BetterCounter, Client, Counter


@pytest.fixture
def box():
    container = Container("box", clock=VirtualClock(seed=1))
    container.install_factory(ComponentFactory("Counter", Counter))
    container.install_factory(ComponentFactory("Client", Client))
    yield container
    container.close()


def test_create_find_by_name_and_type_and_destroy(box):
    a = box.create("Counter", "a")
    b = box.create("Counter", "b", properties={"limit": 3})
    box.create("Client", "c")
    assert box.find("a") == a
    assert [r.name for r in box.find_by_type("Counter")] == ["a", "b"]
    assert b.get("limit") == 3
    assert a.bump(5) == 5
    box.destroy("a")
    assert [r.name for r in box.components()] == ["b", "c"]
    with pytest.raises(ComponentNotFoundError, match="no component named 'a'"):
        box.find("a")


def test_call_to_destroyed_component_raises_a_clear_error(box):
    ref = box.create("Counter", "a")
    box.destroy("a")
    with pytest.raises(ComponentDestroyedError, match="'a' was destroyed at t=0") as info:
        ref.bump()
    assert "find() or create()" in str(info.value)
    # A new component under the same name is not reachable through the stale handle.
    box.create("Counter", "a")
    with pytest.raises(ComponentDestroyedError):
        ref.value()
    assert not ref.alive


def test_unknown_type_duplicate_name_and_bad_property_say_what_to_do(box):
    with pytest.raises(
        FactoryError, match=r"no factory for component type 'Nope' \(installed: Client, Counter\)"
    ):
        box.create("Nope", "x")
    box.create("Counter", "a")
    with pytest.raises(FactoryError, match="already exists"):
        box.create("Counter", "a")
    with pytest.raises(BindingError, match=r"no property 'cuont' \(properties: count, limit\)"):
        box.set_property("a", "cuont", 1)
    with pytest.raises(FactoryError, match="already installed"):
        box.install_factory(ComponentFactory("Counter", Counter))
    with pytest.raises(ComponentError, match="has no operation 'bumpp'"):
        box.find("a").bumpp()


def test_factory_removed_while_instances_live(box):
    destroyed = []
    box.install_factory(
        ComponentFactory("Tracked", Counter, destroy=lambda c: destroyed.append(c.name))
    )
    live = box.create("Tracked", "t1")
    box.remove_factory("Tracked")
    # Stated behaviour: no new instance; live ones keep working and are still found by type.
    with pytest.raises(FactoryError, match="no factory for component type 'Tracked'"):
        box.create("Tracked", "t2")
    assert live.bump() == 1
    assert [r.name for r in box.find_by_type("Tracked")] == ["t1"]
    # Destroying it later still runs the removed factory's destroy hook.
    box.destroy("t1")
    assert destroyed == ["t1"]


def test_factory_removed_with_destroy_instances(box):
    box.install_factory(ComponentFactory("Tracked", Counter))
    ref = box.create("Tracked", "t1")
    box.remove_factory("Tracked", destroy_instances=True)
    assert not ref.alive
    assert box.factories() == ["Client", "Counter"]


def test_factories_installed_at_run_time_vary_the_types(box):
    with pytest.raises(FactoryError):
        box.create("Better", "x")
    box.install_factory(ComponentFactory("Better", BetterCounter))
    assert box.create("Better", "x").bump() == 2


def test_every_state_change_is_an_event(box):
    seen = []
    box.subscribe("*", lambda e: seen.append((e.kind, e.element, e.attribute)), name="spy")
    ref = box.create("Counter", "a")
    ref.bump()
    box.set_property("a", "limit", 4)
    box.set_property("a", "limit", 4)  # no change, no event
    box.destroy("a")
    assert seen == [
        (ev.COMPONENT_CREATED, "a", None),
        (ev.PROPERTY_CHANGED, "a", "count"),
        (ev.OPERATION_CALLED, "a", "bump"),
        (ev.PROPERTY_CHANGED, "a", "limit"),
        (ev.COMPONENT_DESTROYED, "a", None),
    ]


class Recorder(Interceptor):
    def __init__(self) -> None:
        self.calls: list[tuple[str, str, str, object]] = []

    def before(self, call: Invocation) -> None:
        self.calls.append(("before", call.component, call.operation, call.args))

    def after(self, call: Invocation) -> None:
        self.calls.append(("after", call.component, call.operation, call.result))


class Exploding(Interceptor):
    name = "exploding"

    def before(self, call: Invocation) -> None:
        raise KeyError("interceptor bug")

    def after(self, call: Invocation) -> None:
        raise ValueError("interceptor bug after")


class DenyFail(Interceptor):
    def before(self, call: Invocation) -> None:
        if call.operation == "bump" and call.args and call.args[0] > 100:
            raise CallVetoed("bumps above 100 are refused")


def test_interceptors_see_calls_before_and_after_with_filters(box):
    rec, only_b = Recorder(), Recorder()
    box.add_interceptor(rec)
    box.add_interceptor(only_b, component="b")
    box.create("Counter", "a").bump(2)
    box.create("Counter", "b").value()
    assert rec.calls == [
        ("before", "a", "bump", (2,)),
        ("after", "a", "bump", 2),
        ("before", "b", "value", ()),
        ("after", "b", "value", 0),
    ]
    assert only_b.calls == [("before", "b", "value", ()), ("after", "b", "value", 0)]


def test_raising_interceptor_is_isolated_logged_and_counted(box, caplog):
    rec = Recorder()
    box.add_interceptor(Exploding())
    box.add_interceptor(rec)
    ref = box.create("Counter", "a")
    with caplog.at_level(logging.ERROR):
        assert ref.bump() == 1
        assert ref.bump() == 2
    assert box.faults.counts["interceptor"] == 4
    faults = box.faults.of_kind("interceptor")
    assert faults[0].where == "exploding"
    assert faults[0].context == {"phase": "before", "call": "a.bump"}
    assert "KeyError" in faults[0].error
    assert len(rec.calls) == 4  # the other interceptor still ran every time
    assert any(
        "exploding" in r.getMessage() and "isolated" in r.getMessage() for r in caplog.records
    )


def test_veto_reaches_the_caller_and_the_call_does_not_run(box):
    box.add_interceptor(DenyFail())
    ref = box.create("Counter", "a")
    with pytest.raises(CallVetoed, match="refused"):
        ref.bump(500)
    assert ref.get("count") == 0
    assert box.stats["vetoed"] == 1
    assert box.faults.counts["total"] == 0


def test_raising_component_is_isolated_and_the_container_carries_on(box):
    rec = Recorder()
    box.add_interceptor(rec)
    ref = box.create("Counter", "a")
    with pytest.raises(ComponentError, match=r"raised ZeroDivisionError in fail\(\)") as info:
        ref.fail()
    assert isinstance(info.value.__cause__, ZeroDivisionError)
    assert box.faults.counts["component"] == 1
    assert rec.calls[-1] == ("after", "a", "fail", None)
    assert ref.bump() == 1


def test_raising_listener_is_isolated(box):
    def bad(_event):
        raise RuntimeError("listener bug")

    box.subscribe(ev.COMPONENT_CREATED, bad, name="bad-listener")
    box.create("Counter", "a")
    box.create("Counter", "b")
    assert box.faults.counts["listener"] == 2
    assert [r.name for r in box.components()] == ["a", "b"]


def test_raising_on_start_does_not_prevent_hosting():
    class Grumpy(Counter):
        def on_start(self) -> None:
            raise OSError("device missing")

    with Container("c", clock=VirtualClock()) as c:
        c.install_factory(ComponentFactory("Grumpy", Grumpy))
        ref = c.create("Grumpy", "g")
        assert ref.bump() == 1
        assert c.faults.recent[0].context == {"phase": "on_start"}


def test_failing_factory_create_reports_the_type_and_name(box):
    def broken(**config):
        raise RuntimeError(f"no hardware for {config}")

    box.install_factory(ComponentFactory("Broken", Counter, create=broken))
    with pytest.raises(ComponentError, match="factory 'Broken' failed to create 'x'"):
        box.create("Broken", "x", port="/dev/null")
    assert box.find_by_type("Broken") == []


def test_sync_port_call_through_in_process_connector_is_intercepted(box):
    rec = Recorder()
    box.add_interceptor(rec, component="srv")
    box.create("Counter", "srv")
    client = box.create("Client", "cli")
    box.connect("cli.api", "srv.api")
    assert client.use(3) == 3
    assert ("before", "srv", "bump", (3,)) in rec.calls
    with pytest.raises(PortError, match="already connected"):
        box.connect("cli.api", "srv.api", name="second")


def test_port_exposes_only_its_operations(box):
    box.create("Counter", "srv")
    box.create("Client", "cli")
    conn = box.connect("cli.api", "srv.api")
    with pytest.raises(PortError, match="does not expose 'fail'"):
        conn.connector.call(conn, conn.provided, "fail", (), {})


def test_connect_checks_kinds_and_roles(box):
    box.create("Counter", "a")
    box.create("Counter", "b")
    with pytest.raises(PortError, match="both are provided"):
        box.connect("a.api", "b.api")
    with pytest.raises(PortError, match="no port 'nope'"):
        box.connect("a.nope", "b.api")
    with pytest.raises(PortError, match=r"'Component\.port'"):
        box.connect("a", "b.api")


def test_destroying_a_component_drops_its_connections(box):
    box.create("Counter", "srv")
    client = box.create("Client", "cli")
    box.connect("cli.api", "srv.api")
    box.destroy("srv")
    assert box.connections() == []
    with pytest.raises(PortError, match=r"call\(\) on port cli.api, which is not connected"):
        client.use()
    assert box.faults.recent[-1].where == "cli.use"


def test_replacing_by_a_type_without_an_unconnected_port(box):
    # Only connected ports need a counterpart; an unconnected one simply goes away.
    class Portless(CtxComponent):
        def value(self) -> int:
            return 7

    box.install_factory(ComponentFactory("Portless", Portless))
    ref = box.create("Counter", "a")
    box.replace("a", "Portless")
    assert ref.value() == 7
    assert box.find("a").instance.port_map == {}
