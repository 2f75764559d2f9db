"""The console shows the changes of the model applied to its running experiment (``model.updated``
events of its containers, as ``acordcs-gen update`` applies them through a container's management
interface): each plan line is an event of the page's timeline."""

from __future__ import annotations

import importlib
import time

from weblab_console.server import simulation_console
from weblab_console.session import ConsoleSession

from acordcs.console.fanout import ConsoleHub
from acordcs.descriptor import to_xml
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management import Management
from tests.samples.weblab.conftest import APP_DIR
from tests.support import weblab_models as models

SLOW = "smallNarrow: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is slow"


def test_an_update_is_an_event_of_the_console(weblab_app, tmp_path):
    hub = ConsoleHub()
    session = ConsoleSession(hub, "token", speed=5.0)
    console = simulation_console(hub, session)  # the console's page watches the experiment
    console.attach()
    _, box = hub.join(lambda: None)
    try:
        session.start("residential", 0)
        app = session.application
        registry = importlib.import_module("weblab_app.registry")
        data = (APP_DIR / "weblab_app" / "descriptor.xml").read_bytes()
        managed = Management(app, "WebLabSide", data,
                             classes=GivenClasses(registry.FACTORIES, registry.MONITORS))  # fmt: skip
        path = models.write_weblab(
            tmp_path / "weblab.xmi", models.rule(SLOW, SLOW.replace("slow", "fast"))
        )
        new = to_xml(describe(read_model(str(path)).architecture))
        running = time.monotonic() + 30  # the run under way, its clock past 0 (a loaded host)
        while session.sim_time <= 0:
            assert time.monotonic() < running, "the experiment's clock never moved"
            time.sleep(0.05)
        before = session.sim_time
        reply = managed.apply(new.decode(), managed.digest)
        assert reply["status"] == "applied", reply
        line = "~ policy set SpeedLimiting: rule smallNarrow: ... is slow -> ... is fast"
        deadline = time.monotonic() + 10
        seen: list[dict] = []
        while not any(e.get("kind") == "model.updated" for e in seen):
            assert time.monotonic() < deadline, seen[-5:]
            seen += hub.take(box)[1]
            time.sleep(0.05)
        (event,) = [e for e in seen if e.get("kind") == "model.updated"]
        assert event["line"] == line and before > 0
        assert event["time"] >= before - 0.005, (event["time"], before)  # the run's time
    finally:
        console.close()
