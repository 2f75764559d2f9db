"""An application's panels on the console's page come from the console's panel table
(acordcs.plugins): the entry points of ``acordcs.console_panels`` (given here in place of
importlib.metadata's) and a script's own; one that is not a panel, or that takes a command of
the console's own, is refused with why and the others load; a panel belongs on the console of an
application it applies to only. The WebLab's panel and the page around it: tests/samples/weblab_console."""

from __future__ import annotations

from importlib import metadata, resources

from acordcs.console.panels import ENTRY_POINT_GROUP, ConsolePanel, panel_table, panels_for
from tests.support.descriptors import application, component, container, ref


def panel(name: str, needs: str, commands: frozenset[str] = frozenset()) -> ConsolePanel:
    return ConsolePanel(
        name=name,
        title=name,
        static=resources.files("acordcs.console") / "static",
        applies=lambda d: needs in {n for c in d.containers for n in c.hosted("component")},
        attach=lambda context: object(),
        commands=commands,
    )


CAMERA = panel("camera", "Camera")
TAKES_CALL = panel("greedy", "Camera", frozenset({"call", "zoom"}))


def listed(asked: str) -> list[metadata.EntryPoint]:
    pairs = (
        ("camera", f"{__name__}:CAMERA"),
        ("greedy", f"{__name__}:TAKES_CALL"),
        ("number", "math:pi"),
    )
    return (
        [metadata.EntryPoint(n, v, ENTRY_POINT_GROUP) for n, v in pairs]
        if asked == ENTRY_POINT_GROUP
        else []
    )


def test_panels_come_from_entry_points_and_a_scripts_own_and_the_wrong_ones_are_said():
    own = panel("fan", "Fan")
    table = panel_table(entry_points=listed, extra={"fan": own})
    assert table.load() == {"camera": CAMERA, "fan": own}
    problems = table.take_problems()
    assert any("greedy" in p and "the console's own commands call" in p for p in problems), problems
    assert any("number = math:pi" in p and "not an acordcs.console.panels.ConsolePanel" in p
               for p in problems), problems  # fmt: skip
    lab = application(
        "Lab",
        containers=(container("lab", ref("component", "Camera")),),
        components=(component("Camera"),),
    )
    assert panels_for(lab, table) == [CAMERA]  # the fan's panel is for another application
    assert CAMERA.shown()["script"] == "/panels/camera/panel.js"
