"""``replace()`` while an operation of the component is running in another thread (issue 14):
the operation's write reaches the new instance; calls arriving meanwhile run on the new one."""

from __future__ import annotations

import threading
from typing import ClassVar

import pytest

from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.errors import ComponentError


class Slow(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"count": 0}
    state_fields = ("history",)
    started: ClassVar[threading.Event]
    go: ClassVar[threading.Event]

    def __init__(self) -> None:
        self.history: list[str] = []

    def slow_bump(self) -> int:
        count = int(self.get("count"))  # type: ignore[call-overload]
        type(self).started.set()
        type(self).go.wait(10)
        self.history.append(f"bump by {type(self).__name__}")
        self.set("count", count + 1)
        return count + 1

    def who(self) -> str:
        return type(self).__name__


class Faster(Slow):
    pass


@pytest.fixture
def box():
    Slow.started, Slow.go = threading.Event(), threading.Event()
    container = Container("box")
    for cls in (Slow, Faster):
        container.install_factory(ComponentFactory(cls.__name__, cls))
    container.create("Slow", "c")
    yield container
    Slow.go.set()
    container.close()


def test_an_in_flight_write_reaches_the_new_instance(box):
    ref = box.find("c")
    results: dict[str, object] = {}
    caller = threading.Thread(target=lambda: results.update(bump=ref.slow_bump()))
    caller.start()
    assert Slow.started.wait(10)
    replacing = threading.Thread(target=lambda: results.update(new=box.replace("c", "Faster")))
    replacing.start()
    late = threading.Thread(target=lambda: results.update(late=ref.who()))
    late.start()
    Slow.go.set()  # the running operation finishes: then the replacement, then the late call
    for t in (caller, replacing, late):
        t.join(10)
    assert results["bump"] == 1
    assert type(ref.instance) is Faster
    assert ref.get("count") == 1
    assert ref.instance.history == ["bump by Slow"]
    assert results["late"] == "Faster"


def test_a_call_that_does_not_return_stops_the_replacement_cleanly(box):
    ref = box.find("c")
    caller = threading.Thread(target=ref.slow_bump)
    caller.start()
    assert Slow.started.wait(10)
    with pytest.raises(ComponentError, match=r"1 call\(s\) still running"):
        box.replace("c", "Faster", drain_timeout=0.2)
    assert type(ref.instance) is Slow
    Slow.go.set()
    caller.join(10)
    assert ref.get("count") == 1
    assert ref.who() == "Slow"  # the gate is open again
