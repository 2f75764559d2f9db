"""A container assembled with a run directory keeps the state of the components the model tags
``persistent`` there: their properties and state fields, written a moment after a change (a burst
of changes coalesced into one write) and at stop, each write replacing the file whole; assembled
again from the same directory, such a component has that state before its ``on_start`` runs. A
component not tagged starts from the model's initial values, and nothing is kept without a run
directory."""

from __future__ import annotations

import contextlib
import json
import os
import threading
import time
from typing import ClassVar

import pytest

from acordcs.descriptor import to_xml
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import RealClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management import Management, digest
from acordcs.runtime.persistence import Persistence, StateStore, state_file
from tests.support.descriptors import application, component, container, prop, ref

TOKEN = "house-token"


class Fan(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 20.0, "filterHours": 0}
    state_fields = ("log",)
    seen_at_start: tuple[object, list[str]] | None = None

    def __init__(self) -> None:
        self.log: list[str] = []

    def on_start(self) -> None:
        Fan.seen_at_start = (self.props["filterHours"], list(self.log))

    def on_stop(self) -> None:
        self.log.append("stopped")


def home(fan_persistent: bool = True, hours: int = 0, level: int = 1):
    return application(
        "Home",
        containers=(container("house", ref("component", "Fan"), ref("component", "Lamp")),),
        components=(
            component(
                "Fan",
                properties=(prop("speed", 20.0), prop("filterHours", hours)),
                persistent=fan_persistent,
            ),
            component("Lamp", properties=(prop("level", level),)),
        ),
    )


def run(state_dir, app=None):
    return assemble(
        app or home(), factories={"Fan": Fan}, clock=RealClock(), state_dir=state_dir, token=TOKEN
    )


def wait_for(condition, what: str, timeout: float = 10.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"not within {timeout} s: {what}"
        time.sleep(0.01)


def on_disk(run_dir) -> dict:
    try:
        return json.loads(state_file(run_dir, "Fan").read_text())["state"]
    except (FileNotFoundError, json.JSONDecodeError):
        return {}


def test_the_state_is_on_disk_soon_after_a_change_and_restored_before_on_start(tmp_path, capsys):
    with run(tmp_path) as app:
        house = app.container("house")
        house.set_property("Fan", "filterHours", 321)
        house.set_property("Lamp", "level", 9)
        house.instance("Fan").log.append("purged")
        wait_for(lambda: on_disk(tmp_path).get("properties", {}).get("filterHours") == 321,
                 "the change written")  # fmt: skip
    # closed: the last write holds what on_stop left
    assert on_disk(tmp_path) == {
        "properties": {"speed": 20.0, "filterHours": 321},
        "fields": {"log": ["purged", "stopped"]},
    }
    assert not state_file(tmp_path, "Lamp").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["Fan.state.json"]  # no temporary left
    Fan.seen_at_start = None
    with run(tmp_path) as app:
        house = app.container("house")
        assert Fan.seen_at_start == (321, ["purged", "stopped"])
        assert house.get_property("Fan", "filterHours") == 321
        assert house.get_property("Lamp", "level") == 1  # not persistent: the model's value
    assert "Fan: state restored from" in capsys.readouterr().err


def test_without_a_run_directory_or_the_tag_nothing_is_kept(tmp_path):
    with run(None) as app:
        app.container("house").set_property("Fan", "filterHours", 5)
    with run(tmp_path, home(fan_persistent=False)) as app:
        app.container("house").set_property("Fan", "filterHours", 5)
    assert list(tmp_path.iterdir()) == []


def test_a_forged_file_leaves_the_models_values_and_is_kept_aside(tmp_path, capsys):
    state_file(tmp_path, "Fan").write_text(
        json.dumps(
            {
                "format": "acordcs-state/1",
                "application": "Home",
                "component": "Fan",
                "state": {"properties": {"filterHours": 9999}, "fields": {}},
                "hmac-sha256": "0" * 64,
            }
        )
    )
    Fan.seen_at_start = None
    with run(tmp_path) as app:
        assert app.container("house").get_property("Fan", "filterHours") == 0
        assert Fan.seen_at_start == (0, [])
    err = capsys.readouterr().err
    assert f"warning: Fan: state file {state_file(tmp_path, 'Fan')} refused: its signature" in err
    assert len(list(tmp_path.glob("Fan.state.json.refused-*"))) == 1


def container_with_store(tmp_path, interval: float):
    house = Container("house", clock=RealClock())
    house.install_factory(ComponentFactory("Fan", Fan))
    house.create("Fan", "Fan")
    store = StateStore(tmp_path, "Home", home().components[0], token=TOKEN)
    return house, store, Persistence(house, {"Fan": store}, interval=interval)


def test_a_burst_of_changes_is_coalesced(tmp_path):
    house, _, persistence = container_with_store(tmp_path, interval=60.0)
    try:
        wait_for(lambda: persistence.writes == 1, "the first write, at once")
        for hours in range(1, 201):
            house.set_property("Fan", "filterHours", hours)
        assert persistence.writes == 1  # the next one waits for the interval
        persistence.close()
        assert persistence.writes == 2  # and the stop's
        assert on_disk(tmp_path)["properties"]["filterHours"] == 200
    finally:
        persistence.close()
        house.close()


def test_each_write_replaces_the_file_whole_and_is_synced(tmp_path, monkeypatch):
    house, store, persistence = container_with_store(tmp_path, interval=0.0)
    seen: list[object] = []
    stop = threading.Event()

    def read_all_the_time() -> None:
        while not stop.is_set():
            with contextlib.suppress(FileNotFoundError):
                seen.append(json.loads(state_file(tmp_path, "Fan").read_bytes()))

    reader = threading.Thread(target=read_all_the_time)
    reader.start()
    try:
        for hours in range(300):
            house.set_property("Fan", "filterHours", hours)
            time.sleep(0.001)
    finally:
        stop.set()
        reader.join()
        persistence.close()
    assert persistence.writes > 2 and seen  # a reader never saw a part of a file (json.loads)
    synced: list[int] = []
    real_fsync = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (synced.append(fd), real_fsync(fd)))
    assert store.write({"properties": {"filterHours": 7}, "fields": {}})
    assert len(synced) == 2  # the file, then its directory

    def crash(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", crash)
    with pytest.raises(OSError, match="No space left"):
        store.write({"properties": {"filterHours": 8}, "fields": {}})
    assert on_disk(tmp_path)["properties"]["filterHours"] == 7  # the old file, whole
    assert sorted(p.name for p in tmp_path.iterdir()) == ["Fan.state.json"]
    house.close()


def test_a_write_that_fails_is_a_fault_of_the_container(tmp_path, monkeypatch):
    house, store, persistence = container_with_store(tmp_path, interval=0.0)
    wait_for(lambda: persistence.writes == 1, "the first write")

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(store, "write", full)
    house.set_property("Fan", "filterHours", 1)
    wait_for(lambda: house.faults.counts["persistence"] >= 1, "the fault recorded")
    persistence.close()
    house.close()
    fault = next(f for f in house.faults.recent if f.kind == "persistence")
    assert fault.where == "Fan" and "No space left on device" in fault.error
    assert fault.context["file"] == str(state_file(tmp_path, "Fan"))


def test_an_update_of_a_default_leaves_a_restored_value_be(tmp_path):
    """A value the kept state gave is a change made at run time, as one made since the start."""
    with run(tmp_path) as app:
        app.container("house").set_property("Fan", "filterHours", 321)
    with run(tmp_path) as app:
        assert app.restored == {"house": frozenset({("Fan", "filterHours")})}
        old = to_xml(home())
        managed = Management(app, "house", old, classes=GivenClasses({"Fan": Fan}))
        reply = managed.apply(to_xml(home(hours=5, level=2)).decode(), digest(old))
        assert reply["status"] == "applied", reply
        house = app.container("house")
        assert house.get_property("Fan", "filterHours") == 321
        assert house.get_property("Lamp", "level") == 2
        assert any("filterHours" in line for line in reply["kept"]), reply
