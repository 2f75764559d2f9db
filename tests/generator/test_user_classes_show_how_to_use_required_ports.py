"""The user class a build writes once shows, for each required port of its component, how to use
it: for a synchronous port the call of every operation of the component it is connected to,
``self.port("NavLocomotionPort").call("move", speed, turn)``, with the model's parameter names
(typed in a comment, the result bound when there is one); for an asynchronous or stream port
where what its peers send arrives (a handler ``on_<port>``, else ``take()``); for an unconnected
one, that it is not connected. The lines are run here, as they are written, against the running
application (the WebLab's containers assembled in this process): each call reaches the operation
with its arguments and gives back its result, and each message or stream item sent arrives where
the lines say. The ``java`` target's user class lists the same ports with the Java signatures of
what they reach, and says that the Java API makes no call. Only the user files show it: the base
classes hold no such line."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

from acordcs.generator.targets import targets
from acordcs.runtime.api import VirtualClock, assemble
from tests.support.generator import build, context, imported
from tests.support.toolchain import ROOT, WEBLAB

PACKAGE = "weblab_app"
# A value of each Python type the hints annotate parameters with, and what the provider returns.
VALUES = {"float": 1.5, "int": 7, "str": "text", "bool": True}


@pytest.fixture(scope="module")
def out(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("ports")
    result = build(WEBLAB, out, "-t", "python,java")
    assert result.code == 0, result.both
    return out


def hints(out: Path, component: str) -> list[str]:
    """The code lines the user class of ``component`` shows for its required ports."""
    text = (out / PACKAGE / "components" / f"{component}.py").read_text(encoding="utf-8")
    block = text.split("    # Its required ports, and how to use each", 1)[1]
    return [
        line[len("    #     ") :] for line in block.splitlines() if line.startswith("    #     ")
    ]


def test_the_navigators_class_shows_each_ports_use(out: Path):
    shown = (out / PACKAGE / "components" / "Navigator.py").read_text(encoding="utf-8")
    for line in (
        "    #   NavLocomotionPort (synchronous), to Locomotion.LocomotionPort (connection "
        "LocomotionLink):",
        '    #     self.port("NavLocomotionPort").call("move", speed, turn)  # speed: float, '
        "turn: float",
        '    #     self.port("NavLocomotionPort").call("stop")',
        '    #     result = self.port("NavLocomotionPort").call("odometry")  # -> str',
        '    #     result = self.port("NavAccessPort").call("authenticate", user, token)  # user: '
        "str, token: str -> bool",
        "    #   NavTelemetryPort (asynchronous), from Locomotion.TelemetryPort (connection "
        "TelemetryLink):",
        "    #     def on_NavTelemetryPort(self, message: object) -> None:  # gets each message "
        "sent, or:",
        '    #     message = self.port("NavTelemetryPort").take()  # the oldest queued, or None',
        '    #     item = self.port("NavPanoramaPort").take()  # the oldest queued, or None',
    ):
        assert f"\n{line}\n" in shown, line
    assert shown.endswith("    pass\n")
    # A component without required ports shows nothing of the kind; no base class does.
    assert "required ports" not in (out / PACKAGE / "components" / "Access.py").read_text()
    for base in (out / PACKAGE / "base").glob("*.py"):
        assert ".call(" not in base.read_text(encoding="utf-8"), base


def test_the_docs_show_the_navigators_class_as_written(out: Path):
    page = (ROOT / "docs" / "build.md").read_text(encoding="utf-8")
    (excerpt,) = re.findall(r"^```python\n(class Navigator\(NavigatorBase\):\n.*?)^```$", page,
                            flags=re.S | re.M)  # fmt: skip
    assert excerpt in (out / PACKAGE / "components" / "Navigator.py").read_text(encoding="utf-8")


def recorder(operation: str, returns: object, calls: list):
    def method(self, *args):
        calls.append((self.name, operation, args))
        return returns

    method.__name__ = operation
    return method


def test_the_calls_shown_run_the_connected_components_operations(out: Path):
    calls: list[tuple[str, str, tuple]] = []
    with imported(out, PACKAGE) as pkg:
        app = pkg.descriptor()
        returns = {"authenticate": True, "countUsers": 3, "odometry": "{}", "grab": b"frame"}
        factories = dict(pkg.FACTORIES)
        for name in ("Access", "Locomotion", "Vision"):
            comp = next(c for c in app.components if c.name == name)
            methods = {
                o.name: recorder(o.name, returns.get(o.name), calls) for o in comp.operations
            }
            factories[name] = type(name, (pkg.FACTORIES[name],), methods)
        with assemble(app, factories=factories, monitors=pkg.MONITORS, clock=VirtualClock()) as run:
            tried = 0
            for component, host in (("Navigator", "UserSide"), ("Recovery", "WebLabSide")):
                instance = run.container(host).find(component).instance
                for line in hints(out, component):
                    if ".call(" not in line:
                        continue
                    code, _, typed = line.partition("  # ")
                    params = re.findall(r"(\w+): (\w+)", typed.split("->")[0])
                    scope = {"self": instance, **{n: VALUES[t] for n, t in params}}
                    calls.clear()
                    exec(code, scope)  # the line as the class shows it
                    operation = re.search(r'\.call\("(\w+)"', code)[1]
                    provider = "Vision" if "Vision" in code else (
                        "Access" if "Access" in code else "Locomotion")  # fmt: skip
                    assert calls == [(provider, operation, tuple(VALUES[t] for _, t in params))]
                    if code.startswith("result = "):
                        assert scope["result"] == returns[operation]
                    tried += 1
    assert (
        tried == 9
    )  # Navigator: 2 + 3 + 1 through NavAccess, NavLocomotion, NavVision; Recovery: 3


def test_what_is_sent_to_a_required_port_arrives_where_shown(out: Path):
    navigator_lines = hints(out, "Navigator")
    (handler,) = [line for line in navigator_lines if line.startswith("def on_NavTelemetryPort(")]
    (take,) = [line for line in navigator_lines if ' = self.port("NavPanoramaPort").take()' in line]
    received: list[object] = []
    with imported(out, PACKAGE) as pkg:
        # The handler as shown, with a body: the Navigator's subclass defines it.
        scope: dict = {"received": received}
        exec(f"{handler.partition('  # ')[0]}\n    received.append(message)\n", scope)
        navigator = type("Navigator", (pkg.FACTORIES["Navigator"],),
                         {"on_NavTelemetryPort": scope["on_NavTelemetryPort"]})  # fmt: skip
        factories = {**pkg.FACTORIES, "Navigator": navigator}
        clock = VirtualClock()
        app = pkg.descriptor()
        with assemble(app, factories=factories, monitors=pkg.MONITORS, clock=clock) as run:
            user, lab = run.container("UserSide"), run.container("WebLabSide")
            lab.find("Locomotion").instance.port("TelemetryPort").notify("telemetry 1")
            lab.find("PanoramicCamera").instance.port("CameraStreamPort").push(b"panorama 1")
            clock.run_for(1.0)
            assert received == ["telemetry 1"]
            scope = {"self": user.find("Navigator").instance}
            exec(take.partition("  # ")[0], scope)
            assert scope["item"] == b"panorama 1"
            exec(take.partition("  # ")[0], scope)
            assert scope["item"] is None  # "or None": nothing more is queued


def test_an_unconnected_required_port_says_so(tmp_path: Path, weblab):
    app = dataclasses.replace(
        weblab, connections=tuple(c for c in weblab.connections if c.name != "VisionLink")
    )
    for target, path, said in (
        ("python", f"{PACKAGE}/components/Navigator.py", "    #   NavVisionPort (synchronous): "
         "not connected in the model (using it raises PortError until a connection joins it to "
         "a provided port)\n"),
        ("java", "java/weblab/Navigator.java",
         "    //   NavVisionPort (synchronous): not connected in the model\n"),
    ):  # fmt: skip
        made = context(app, tmp_path, target=target, source="weblab.xmi")
        targets()[target].run(made)
        (text,) = [f.data.decode("utf-8") for f in made.files if f.path == path]
        assert said in text


def test_the_java_user_class_lists_what_each_required_port_reaches(out: Path):
    text = (out / "java" / "weblab" / "Navigator.java").read_text(encoding="ascii")
    block = text.split("public class Navigator extends NavigatorBase {\n", 1)[1].split("\n\n")[0]
    assert block.splitlines() == [
        "    // Its required ports: a synchronous one calls as port(name).call(operation, "
        "arguments...)",
        "    // (the result boxed: a Double, Long, Boolean or String), an asynchronous one sends "
        "with",
        "    // port(name).notify(message), a stream one with push(item). What each reaches:",
        "    //   NavAccessPort (synchronous), to Access.AccessPort (connection AccessLink):",
        "    //     boolean authenticate(java.lang.String user, java.lang.String token)",
        "    //     int countUsers()",
        "    //   NavLocomotionPort (synchronous), to Locomotion.LocomotionPort (connection "
        "LocomotionLink):",
        "    //     void move(double speed, double turn)",
        "    //     void stop()",
        "    //     java.lang.String odometry()",
        "    //   NavPanoramaPort (stream), from PanoramicCamera.CameraStreamPort (connection "
        "PanoramaLink): receives what it sends",
        "    //   NavTelemetryPort (asynchronous), from Locomotion.TelemetryPort (connection "
        "TelemetryLink): receives what it sends",
        "    //   NavVisionPort (synchronous), to Vision.VisionPort (connection VisionLink):",
        "    //     java.lang.Object grab()",
    ]
    assert "required ports" not in (out / "java" / "weblab" / "NavigatorBase.java").read_text()
