"""Rebuild the BOUML-style sample models: ``weblab/weblab.xmi`` and ``smartroom/smartroom.xmi``,
and the two copies of the WebLab model with mistakes that the documentation's examples validate
(``mistakes/broken-weblab.xmi``, ``mistakes/typos.xmi``), and beside each sample its model in the
text notation (``weblab/weblab.acord``, ``smartroom/smartroom.acord``: what ``acordcs-gen convert``
writes from it).

The samples are what BOUML's xmi2 exporter writes for the models described in each sample's README.
They are written by the same writer as the synthetic benchmark model
(`tools/bouml_writer`), so that both places BOUML puts a stereotype (root-level
application, ``xmi:Extension``) always agree. Run ``.venv/bin/python samples/build_samples.py``;
the output is deterministic.
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # the repository: tools/ is not installed
from tools.bouml_writer.bouml import BoumlWriter, ctx, ctx_var  # noqa: E402
from tools.bouml_writer.elements import Pkg  # noqa: E402

# ------------------------------------------------------------------------------------------ WebLab
# Linguistic terms (our choices; the paper gives names of some terms, never their shapes).
CYCLE_RATE = "small := trape 0 0 0.8 1.2; medium := trian 0.9 1.4 1.9; large := trape 1.5 2 3 3"
ANGLE = (
    "narrow := trape 0 0 5 15; medium := trian 5 20 35; wide := trian 25 45 65;"
    " sharp := trape 55 70 90 90"
)
SPEED = "stopped := trape 0 0 1 10; slow := trian 5 60 150; fast := trape 100 200 500 500"
MAX_SPEED = (
    "crawl := trape 0 0 20 50; slow := trian 30 70 110; medium := trian 80 120 160;"
    " fast := trape 130 160 200 200"
)
NUM_USERS = "low := trape 0 0 1 3; medium := trian 2 4 7; high := trape 5 8 10 10"
FPS = "low := trape 0 0 1 3; medium := trian 2 4 8; high := trape 6 12 15 15"

# SpeedLimiting: cycleRate x angle -> Locomotion.maxSpeed (12 rules, in two policies).
SPEED_TABLE = {
    ("small", "narrow"): "slow",
    ("small", "medium"): "slow",
    ("medium", "narrow"): "medium",
    ("medium", "medium"): "medium",
    ("large", "narrow"): "fast",
    ("large", "medium"): "medium",
    ("small", "wide"): "crawl",
    ("small", "sharp"): "crawl",
    ("medium", "wide"): "slow",
    ("medium", "sharp"): "crawl",
    ("large", "wide"): "slow",
    ("large", "sharp"): "slow",
}
# BandwidthLimiting: cycleRate x numUsers -> PanoramicCamera.fps (9 rules).
FPS_TABLE = {
    ("small", "low"): "medium",
    ("small", "medium"): "low",
    ("small", "high"): "low",
    ("medium", "low"): "high",
    ("medium", "medium"): "medium",
    ("medium", "high"): "low",
    ("large", "low"): "high",
    ("large", "medium"): "high",
    ("large", "high"): "medium",
}


def _speed_rules(angles: tuple[str, ...]) -> str:
    out = []
    for (rate, angle), speed in SPEED_TABLE.items():
        if angle in angles:
            out.append(
                f"{rate}{angle.capitalize()}: if cycleRate is {rate} and angle is {angle} "
                f"then Locomotion.maxSpeed is {speed}"
            )
    return "\n".join(out)


def weblab() -> Pkg:
    root = Pkg("WebLab")
    app = root.package("ContextAwareNavigation")
    comps = app.package("Components")
    adapt = app.package("Adaptation")
    deploy = app.package("Deployment")

    # ---- plain UML: the image type the vision service returns (not an ACORD-CS element)
    image = comps.cls("Image")
    image.attr("width", "int", default="160")
    image.attr("height", "int", default="120")
    image.attr("encoding", "string", default="jpeg")
    image.attr("data", "string")
    image.attr("timestamp", "double")
    image.comment = "A frame of the on-board camera as the vision service returns it."

    # ---- components
    nav = ctx(comps.cls("Navigator"), "CtxComponent", language="python")
    nav.comment = (
        "The user's control program (paper, section 4, steps 1-5): grab an image, find the stripe,"
        " compute a turn, set speed and turn; stop and retry when no stripe is found.\n"
        "The only element deployed on the user's side."
    )
    nav.attr("forwardSpeed", "double", default="100")
    nav.attr("lookAhead", "double", default="300")
    nav.attr("retryDelay", "double", default="2")
    nav.op("run")
    nav.op("step", returns="bool")
    nav.op("findStripe", [("frame", image)], "double")

    vision = ctx(comps.cls("Vision"), "CtxComponent", language="python")
    vision.comment = "The robot's vision service: images of the on-board camera."
    vision.attr("width", "int", default="160")
    vision.attr("height", "int", default="120")
    vision.attr("quality", "int", default="75")
    vision.op("grab", returns=image)

    loco = ctx(comps.cls("Locomotion"), "CtxComponent", language="python")
    loco.comment = (
        "The robot's locomotion service. maxSpeed (mm/s) caps the speed a move() may set;"
        " SpeedLimiting adapts it."
    )
    ctx_var(loco, "maxSpeed", "double", 0, 200, MAX_SPEED, default="200")
    loco.attr("wheelBase", "double", default="330")
    loco.op("move", [("speed", "double"), ("turn", "double")])
    loco.op("stop")
    loco.op("odometry", returns="string")

    access = ctx(comps.cls("Access"), "CtxComponent", language="python")
    access.comment = "The WebLab's access service: reservation and authentication."
    access.attr("maxUsers", "int", default="10")
    access.attr("sessionTimeout", "int", default="1800")
    access.op("authenticate", [("user", "string"), ("token", "string")], "bool")
    access.op("countUsers", returns="int")

    camera = ctx(comps.cls("PanoramicCamera"), "CtxComponent", language="python")
    camera.comment = "The room's network camera; BandwidthLimiting adapts its frame rate."
    ctx_var(camera, "fps", "int", 0, 15, FPS, default="12")
    camera.attr("resolution", "string", default="640x480")
    camera.op("setFrameRate", [("rate", "int")])

    recovery = ctx(comps.cls("Recovery"), "CtxComponent", language="python")
    recovery.comment = (
        "Recovering actions: back the robot up, turn it, cap its speed, then wait."
        " askUser() requests user interference."
    )
    recovery.attr("retries", "int", default="0")
    recovery.attr("recoveries", "int", default="0")
    recovery.attr("lostAt", "double", default="0")
    recovery.attr("backupDistance", "double", default="150")
    recovery.attr("turnAngle", "double", default="20")
    recovery.attr("waitTime", "double", default="3")
    recovery.op("recover")
    recovery.op("askUser")

    # ---- ports (owned by components through associations) and connections
    def port(owner, name, kind, role):
        p = ctx(comps.cls(name), "CtxPort", kind=kind, role=role)
        comps.associate(owner, p, name[0].lower() + name[1:], aggregation="composite")
        return p

    vision_p = port(vision, "VisionPort", "synchronous", "provided")
    loco_p = port(loco, "LocomotionPort", "synchronous", "provided")
    telem_p = port(loco, "TelemetryPort", "asynchronous", "provided")
    access_p = port(access, "AccessPort", "synchronous", "provided")
    camera_p = port(camera, "CameraStreamPort", "stream", "provided")
    camera_p.attr("format", "string", default="mjpeg")
    nav_vision = port(nav, "NavVisionPort", "synchronous", "required")
    nav_loco = port(nav, "NavLocomotionPort", "synchronous", "required")
    nav_access = port(nav, "NavAccessPort", "synchronous", "required")
    nav_telem = port(nav, "NavTelemetryPort", "asynchronous", "required")
    nav_camera = port(nav, "NavPanoramaPort", "stream", "required")
    rec_loco = port(recovery, "RecoveryLocomotionPort", "synchronous", "required")

    def link(name, connector, provided, required, qos=True):
        c = ctx(comps.cls(name), "CtxPortConnection", connector=connector)
        if qos:
            c.attr("latency", "double", default="0")
            c.attr("bandwidth", "double", default="0")
        comps.associate(c, provided, "provider")
        comps.associate(c, required, "consumer")
        return c

    link("VisionLink", "remote", vision_p, nav_vision)
    link("LocomotionLink", "remote", loco_p, nav_loco)
    link("AccessLink", "remote", access_p, nav_access)
    link("TelemetryLink", "remote", telem_p, nav_telem)
    link("PanoramaLink", "shaped", camera_p, nav_camera)
    link("RecoveryLink", "inprocess", loco_p, rec_loco, qos=False)

    # ---- monitors
    control = ctx(adapt.cls("Control"), "CtxMonitor", acquisition="intercept")
    control.comment = (
        "Intercepts the calls to the locomotion service; from the speed and turn set it computes"
        " the control cycle rate (cycles/s) and the trajectory angle (degrees). Event-driven."
    )
    ctx_var(control, "cycleRate", "double", 0, 3, CYCLE_RATE)
    ctx_var(control, "angle", "double", 0, 90, ANGLE)
    ctx_var(control, "speed", "double", 0, 500, SPEED)
    telemetry = ctx(
        adapt.cls("Telemetry"), "CtxMonitor", acquisition="subscribe", xpath="/telemetry"
    )
    telemetry.comment = (
        "Subscribes to the context provider for the robot's telemetry: the documents the"
        " locomotion service publishes, <telemetry> with one child element per attribute."
        " progress (mm) is how far along the stripe the lab has seen the robot get."
    )
    for name in ("positionX", "positionY", "heading", "sonarRange", "batteryVoltage", "progress"):
        telemetry.attr(name, "double")
    usage = ctx(
        adapt.cls("Usage"), "CtxMonitor", acquisition="poll", frequency=1.0, operation="countUsers"
    )
    usage.comment = "Polls the access service for the number of users of the experiment."
    ctx_var(usage, "numUsers", "int", 0, 10, NUM_USERS, default="1")

    adapt.depend(control, loco_p)
    adapt.depend(telemetry, telem_p)  # where its documents come from (read: the xpath)
    adapt.depend(usage, access)

    # ---- policy sets and policies
    speed = ctx(
        adapt.cls("SpeedLimiting"),
        "CtxPolicySet",
        engine="fuzzy",
        semantics="mamdani",
        trigger="event",
    )
    speed.comment = "Limits the robot's speed so that it does not lose the stripe (12 fuzzy rules)."
    recovering = ctx(adapt.cls("Recovering"), "CtxPolicySet", engine="clips", trigger="event")
    recovering.comment = (
        "When the control sets speed 0: recover, at most 3 times, then ask the user."
        " The recovery succeeded when the robot moves again on the stripe, 100 mm or more"
        " ahead of where it lost it."
    )
    bandwidth = ctx(
        adapt.cls("BandwidthLimiting"),
        "CtxPolicySet",
        engine="fuzzy",
        semantics="mamdani",
        trigger="periodic",
        frequency=0.5,
    )
    bandwidth.comment = (
        "Limits the panoramic camera's frame rate to save bandwidth for the control."
    )

    straight = ctx(adapt.cls("StraightRules"), "CtxPolicy", Rule=_speed_rules(("narrow", "medium")))
    turns = ctx(adapt.cls("TurnRules"), "CtxPolicy", Rule=_speed_rules(("wide", "sharp")))
    recover_rules = ctx(
        adapt.cls("RecoveryRules"),
        "CtxPolicy",
        Rule="\n".join(
            (
                # Count first, then decide: a crisp set runs to quiescence, so a rule that counted
                # and a rule that tests the count would both fire on the third zero otherwise.
                "count: if Control.speed == 0 then Recovery.retries = Recovery.retries + 1",
                # Where the robot lost the stripe: how far along it the telemetry last saw it.
                "lost: if Control.speed == 0 and Recovery.retries == 1 then"
                " Recovery.lostAt = Telemetry.progress",
                "retry: if Control.speed == 0 and Recovery.retries <= 3 then Recovery.recover()",
                "giveUp: if Control.speed == 0 and Recovery.retries == 4 then Recovery.askUser()",
                # Moving is not enough: a robot that found the stripe again but follows it
                # backwards, or loses it again at the same place, has not recovered.
                "recovered: if Control.speed > 0 and Recovery.retries > 0"
                " and Telemetry.progress > Recovery.lostAt + 100 then"
                " Recovery.recoveries = Recovery.recoveries + 1 and Recovery.retries = 0",
            )
        ),
    )
    fps_rules = ctx(
        adapt.cls("FrameRateRules"),
        "CtxPolicy",
        Rule="\n".join(
            f"{rate}{users.capitalize()}: if cycleRate is {rate} and numUsers is {users}"
            f" then PanoramicCamera.fps is {fps}"
            for (rate, users), fps in FPS_TABLE.items()
        ),
    )

    adapt.associate(speed, straight, "straightRules", aggregation="composite")
    adapt.associate(speed, turns, "turnRules", aggregation="composite")
    adapt.associate(recovering, recover_rules, "rules", aggregation="composite")
    adapt.associate(bandwidth, fps_rules, "rules", aggregation="composite")
    # feeds (bidirectional for Control, as a modeller draws it; one-way for the others)
    adapt.associate(control, speed, "speedLimiting", back="control")
    adapt.associate(control, recovering, "recovering")
    adapt.associate(control, bandwidth, "bandwidthLimiting")
    adapt.associate(telemetry, recovering, "recovering")
    adapt.associate(usage, bandwidth, "bandwidthLimiting")
    # adapts
    adapt.depend(speed, loco)
    adapt.depend(recovering, recovery)
    adapt.depend(bandwidth, camera)

    # ---- containers and deployment
    user_side = ctx(deploy.cls("UserSide"), "CtxContainer", host="user.example.org")
    user_side.comment = "The user's computer."
    weblab_side = ctx(
        deploy.cls("WebLabSide"), "CtxContainer", host="weblab.example.org", port=47020
    )
    weblab_side.comment = "The WebLab's server: hosts every element except the Navigator."
    deploy.associate(user_side, nav, "navigator", aggregation="composite")
    for c in (vision, loco, access, camera, recovery, control, telemetry, usage):
        deploy.associate(weblab_side, c, c.name[0].lower() + c.name[1:], aggregation="composite")
    for s in (speed, recovering, bandwidth):
        deploy.associate(weblab_side, s, s.name[0].lower() + s.name[1:])
    return root


# --------------------------------------------------------------------------------------- SmartRoom
OCCUPANCY = "empty := trape 0 0 0 1; few := trian 0 3 8; many := trape 5 12 20 20"
DAYLIGHT = "dark := trape 0 0 50 200; dim := trian 100 300 500; bright := trape 400 700 1000 1000"
DIMMER = (
    "off := trape 0 0 5 15; low := trian 10 30 50; medium := trian 40 60 80;"
    " high := trape 70 90 100 100"
)


def smartroom() -> Pkg:
    root = Pkg("SmartRoom")
    app = root.package("MeetingRoom")

    room = ctx(app.cls("Room"), "CtxContainer", host="room-controller.example.org")
    room.comment = "The meeting room's controller: hosts every element of the application."

    lights = ctx(app.cls("Lights"), "CtxComponent", language="python")
    lights.comment = "A dimmable lighting group (DALI gateway)."
    ctx_var(lights, "dimmer", "double", 0, 100, DIMMER, default="0")
    lights.op("setLevel", [("percent", "double")])

    hvac = ctx(app.cls("Hvac"), "CtxComponent", language="python")
    hvac.comment = "The room's heating, ventilation and air-conditioning unit."
    hvac.attr("setpoint", "double", default="21")
    hvac.attr("ecoMode", "bool", default="false")
    hvac.op("setSetpoint", [("celsius", "double")])
    hvac.op("setEco", [("enabled", "bool")])

    sensors = ctx(app.cls("SensorHub"), "CtxComponent", language="python")
    sensors.comment = "Presence, light and temperature sensors."
    sensors.op("read", [("sensor", "string")], "double")
    readings = ctx(app.cls("ReadingsPort"), "CtxPort", kind="asynchronous", role="provided")
    feed = ctx(app.cls("ReadingsFeed"), "CtxPort", kind="asynchronous", role="required")
    hvac_in = ctx(app.cls("HvacControlPort"), "CtxPort", kind="synchronous", role="provided")
    app.associate(sensors, readings, "readingsPort", aggregation="composite")
    app.associate(hvac, hvac_in, "controlPort", aggregation="composite")
    app.associate(hvac, feed, "readingsFeed", aggregation="composite")
    wire = ctx(app.cls("SensorBus"), "CtxPortConnection", connector="inprocess")
    app.associate(wire, readings, "provider")
    app.associate(wire, feed, "consumer")

    presence = ctx(app.cls("Presence"), "CtxMonitor", frequency=0.2)
    presence.comment = "People counted by the presence sensors, and the daylight level (lux)."
    ctx_var(presence, "occupancy", "int", 0, 20, OCCUPANCY, default="0")
    ctx_var(presence, "daylight", "double", 0, 1000, DAYLIGHT)
    climate = ctx(app.cls("Climate"), "CtxMonitor", frequency=0.1)
    climate.attr("temperature", "double")
    climate.attr("minutesEmpty", "int", default="0")
    app.depend(presence, readings)
    app.depend(climate, sensors)

    lighting = ctx(
        app.cls("Lighting"), "CtxPolicySet", engine="fuzzy", trigger="periodic", frequency=0.2
    )
    comfort = ctx(app.cls("Comfort"), "CtxPolicySet", engine="clips", trigger="event")
    light_rules = ctx(
        app.cls("LightRules"),
        "CtxPolicy",
        Rule="\n".join(
            (
                "vacant: if occupancy is empty then Lights.dimmer is off",
                "brightDay: if occupancy is not empty and daylight is bright"
                " then Lights.dimmer is low",
                "dimDay: if (occupancy is few or occupancy is many) and daylight is dim"
                " then Lights.dimmer is medium",
                "night: if occupancy is many and daylight is dark then Lights.dimmer is high",
                "quietNight: if occupancy is few and daylight is very dark"
                " then dimmer is high with 0.8",
            )
        ),
    )
    comfort_rules = ctx(
        app.cls("ComfortRules"),
        "CtxPolicy",
        Rule="\n".join(
            (
                "eco: if Climate.minutesEmpty >= 15 and not Hvac.ecoMode then Hvac.setEco(true)"
                " and Hvac.ecoMode = true",
                "occupied: if Presence.occupancy > 0 and Hvac.ecoMode then Hvac.setEco(false)"
                " and Hvac.ecoMode = false",
                "crowded: if Presence.occupancy > 10 and Climate.temperature > 23"
                " then Hvac.setSetpoint(Hvac.setpoint - 1)",
            )
        ),
    )
    app.associate(lighting, light_rules, "rules", aggregation="composite")
    app.associate(comfort, comfort_rules, "rules", aggregation="composite")
    app.associate(presence, lighting, "lighting")
    app.associate(presence, comfort, "comfort")
    app.associate(climate, comfort, "comfort")
    app.depend(lighting, lights)
    app.depend(comfort, hvac)
    for c in (lights, hvac, sensors, presence, climate, lighting, comfort):
        app.associate(room, c, c.name[0].lower() + c.name[1:], aggregation="composite")
    return root


# The mistakes the documentation shows (README, docs/cli.md, docs/diagnostics.md): each (text of the
# WebLab model, what a modeller mistyped it as): the first occurrence, the rule in both places
# BOUML writes it.
BROKEN = (
    (
        "smallNarrow: if cycleRate is small and angle is narrow",
        "smallNarrow: if cycleRat is small and angle is narow",
        2,
    ),
)
TYPOS = (
    (
        '<ACORDCS:CtxPolicy xmi:id="BOUML_STELT_0x20302_4"',
        '<ACORDCS:CtxPolcy xmi:id="BOUML_STELT_0x20302_4"',
    ),
    ('trigger="periodic" frequency="0.5"', 'triger="periodic" frequency="0.5"'),
    ('engine="fuzzy" semantics', 'engine="fuzy" semantics'),
    ('CtxPolicySet:engine" value="fuzzy"', 'CtxPolicySet:engine" value="fuzy"'),
)


def mistaken(text: str, edits: tuple[tuple, ...]) -> str:
    """``text`` with the first ``count`` (default 1) occurrences of each ``old`` made ``new``."""
    for old, new, *count in edits:
        times = count[0] if count else 1
        if text.count(old) < times:
            raise ValueError(f"{old!r} is not {times} times in the WebLab model")
        text = text.replace(old, new, times)
    return text


def render() -> dict[Path, str]:
    """The sample files and their text."""
    files = {
        HERE / "weblab" / "weblab.xmi": BoumlWriter(
            "WebLab",
            uml_version="2.1",
            exporter_version="4.22.2",
            user_id=0x02,
            first=0x1F400,
            gxmi_path="C:/weblab/uml/weblab.xmi",
        ).write(weblab()),
        HERE / "smartroom" / "smartroom.xmi": BoumlWriter(
            "SmartRoom",
            uml_version="2.3",
            exporter_version="5.1",
            user_id=0x16,
            first=0x1F400,
            gxmi_path="/home/modeller/smartroom/smartroom.xmi",
        ).write(smartroom()),
    }
    weblab_text = files[HERE / "weblab" / "weblab.xmi"]
    files[HERE / "mistakes" / "broken-weblab.xmi"] = mistaken(weblab_text, BROKEN)
    files[HERE / "mistakes" / "typos.xmi"] = mistaken(weblab_text, TYPOS)
    return files


def main() -> int:
    from acordcs.model.outline_builder import to_form
    from acordcs.model.reading import read_model

    for path, text in render().items():
        path.parent.mkdir(exist_ok=True)
        path.write_text(text, encoding="utf-8")
        print(f"{path}: {len(text)} bytes")
        if path.parent.name != "mistakes":  # each sample's text beside it (docs/notation.md)
            beside = path.with_suffix(".acord")
            beside.write_bytes(to_form(read_model(str(path)).architecture, "text"))
            print(f"{beside}: its text")
    return 0


if __name__ == "__main__":
    sys.exit(main())
