"""The WebLab model with a modeller's changes, written as ``samples/build_samples.py`` writes the
sample (the same writer, the same settings): the element ids of what did not change stay the ids
of the sample's elements only where the order allows; updates match elements by name anyway."""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from functools import cache
from pathlib import Path
from types import ModuleType

from tests.support.toolchain import SAMPLES
from tools.bouml_writer.bouml import BoumlWriter, ctx
from tools.bouml_writer.elements import Cls, Pkg

Edit = Callable[[Pkg], None]


@cache
def _samples() -> ModuleType:
    spec = importlib.util.spec_from_file_location("build_samples", SAMPLES / "build_samples.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def weblab_text(*edits: Edit) -> str:
    """The WebLab model's XMI with ``edits`` made to it."""
    root = _samples().weblab()
    for edit in edits:
        edit(root)
    return BoumlWriter(
        "WebLab",
        uml_version="2.1",
        exporter_version="4.22.2",
        user_id=0x02,
        first=0x1F400,
        gxmi_path="C:/weblab/uml/weblab.xmi",
    ).write(root)


def write_weblab(path: Path, *edits: Edit) -> Path:
    path.write_text(weblab_text(*edits), encoding="utf-8")
    return path


def package(root: Pkg, name: str) -> Pkg:
    for p in root.packages:
        if p.name == name:
            return p
        found = _find_package(p, name)
        if found is not None:
            return found
    raise KeyError(name)


def _find_package(pkg: Pkg, name: str) -> Pkg | None:
    for p in pkg.packages:
        if p.name == name:
            return p
        found = _find_package(p, name)
        if found is not None:
            return found
    return None


def element(root: Pkg, name: str) -> Cls:
    stack = [root]
    while stack:
        pkg = stack.pop()
        for c in pkg.classes:
            if c.name == name:
                return c
        stack += pkg.packages
    raise KeyError(name)


# ------------------------------------------------------------------------------ the changes
def rule(old: str, new: str) -> Edit:
    """A rule of SpeedLimiting's policies rewritten (text ``old`` -> ``new``)."""

    def edit(root: Pkg) -> None:
        for policy in ("StraightRules", "TurnRules"):
            tags = element(root, policy).tags
            assert "Rule" in tags
            tags["Rule"] = tags["Rule"].replace(old, new)

    return edit


def default(cls: str, attribute: str, value: str) -> Edit:
    def edit(root: Pkg) -> None:
        found = next(a for a in element(root, cls).attrs if a.name == attribute)
        found.default = value

    return edit


def sessions_monitor(root: Pkg) -> None:
    """A new monitor, Sessions: polls Access.countUsers at 2 Hz, in the WebLab's container,
    feeding BandwidthLimiting (whose rules do not read it)."""
    adapt, deploy = package(root, "Adaptation"), package(root, "Deployment")
    mon = ctx(
        adapt.cls("Sessions"), "CtxMonitor", acquisition="poll", frequency=2.0,
        operation="countUsers",
    )  # fmt: skip
    mon.attr("sessions", "int", default="0")
    adapt.depend(mon, element(root, "Access"))
    adapt.associate(mon, element(root, "BandwidthLimiting"), "bandwidthLimiting")
    deploy.associate(element(root, "WebLabSide"), mon, "sessions", aggregation="composite")


def logger_component(root: Pkg) -> None:
    """A new component, Logger, in the WebLab's container, its required port connected to
    Locomotion's (in-process)."""
    comps, deploy = package(root, "Components"), package(root, "Deployment")
    logger = ctx(comps.cls("Logger"), "CtxComponent", language="python")
    logger.attr("lines", "int", default="0")
    logger.op("note", [("text", "string")])
    port = ctx(comps.cls("LoggerLocomotionPort"), "CtxPort", kind="synchronous", role="required")
    comps.associate(logger, port, "loggerLocomotionPort", aggregation="composite")
    link = ctx(comps.cls("LoggerLink"), "CtxPortConnection", connector="inprocess")
    comps.associate(link, element(root, "LocomotionPort"), "provider")
    comps.associate(link, port, "consumer")
    deploy.associate(element(root, "WebLabSide"), logger, "logger", aggregation="composite")


def broken_component(root: Pkg) -> None:
    """A new component, Broken, in the WebLab's container (its class is made to fail)."""
    comps, deploy = package(root, "Components"), package(root, "Deployment")
    broken = ctx(comps.cls("Broken"), "CtxComponent", language="python")
    broken.attr("level", "int", default="0")
    deploy.associate(element(root, "WebLabSide"), broken, "broken", aggregation="composite")


def without_telemetry(root: Pkg) -> None:
    """The Telemetry monitor removed, and with it what Recovering's rules read of it (the robot's
    progress along the stripe): the lost place is no longer recorded, and a recovery succeeds
    when the robot moves again."""
    adapt, deploy = package(root, "Adaptation"), package(root, "Deployment")
    rules = element(root, "RecoveryRules").tags
    lines = [line for line in rules["Rule"].split("\n") if not line.startswith("lost:")]
    rules["Rule"] = "\n".join(lines).replace(" and Telemetry.progress > Recovery.lostAt + 100", "")
    assert "Telemetry" not in rules["Rule"]
    telemetry = element(root, "Telemetry")
    adapt.classes.remove(telemetry)
    for pkg in (adapt, deploy):
        pkg.assocs = [a for a in pkg.assocs if telemetry not in (a.a.type, a.b.type)]
        pkg.deps = [d for d in pkg.deps if telemetry not in (d.client, d.supplier)]
    for cls in (element(root, "WebLabSide"), element(root, "Recovering")):
        cls.ends = [e for e in cls.ends if e.type is not telemetry]


def vision_moved(root: Pkg) -> None:
    """The Vision component deployed in the user's container instead: not applicable live."""
    deploy = package(root, "Deployment")
    vision = element(root, "Vision")
    for assoc in deploy.assocs:
        if assoc.a.type is vision:
            assoc.a.owner = element(root, "UserSide")
    lab, user = element(root, "WebLabSide"), element(root, "UserSide")
    moved = [e for e in lab.ends if e.type is vision]
    lab.ends = [e for e in lab.ends if e.type is not vision]
    user.ends += moved
