"""A component tagged ``language=java`` runs: its container compiles its class, starts a JVM
(JPype) and hosts it as a Python one (``acordcs.runtime.jvm``), on the sample
``samples/mixed/greenhouse.uml`` built once for the module: the Python sensor and the Java vent
call each other through their ports (synchronous and asynchronous), in process; the shed's
Python panel calls the vent over Pyro5 from another process; the fuzzy policy set writes the
vent's property into its Java field; the vent's own rules use the paper's four calls; a replaced
vent runs its new classes with its properties; a Java exception is a fault with its Java stack,
and the container goes on. A start without javac
or with a Java class that does not compile says so (exit 2, no traceback); a container hosting
no Java component loads no JPype.

Needs a JDK and JPype (``make test`` installs them): outside CI the module skips without them;
with ``CI=true`` it fails.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest

from acordcs.runtime import events as ev
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.container import Container
from acordcs.runtime.errors import ComponentError
from acordcs.runtime.jvm import java_factory
from acordcs.runtime.live.management import Management
from acordcs.runtime.live.reloading import PackageClasses
from tests.support.generator import build
from tests.support.toolchain import SAMPLES

MODEL = SAMPLES / "mixed" / "greenhouse.uml"
PACKAGE = "mixedgreenhouse_app"


def _needs(what: str) -> None:
    if os.environ.get("CI") == "true":
        pytest.fail(f"{what}; CI=true, so it must be installed (make test installs it)")
    pytest.skip(what)


@pytest.fixture(scope="module")
def out(tmp_path_factory: pytest.TempPathFactory) -> Path:
    if shutil.which("javac") is None:
        _needs("no javac on PATH (openjdk-17-jdk-headless)")
    try:
        import jpype  # noqa: F401
    except ImportError:
        _needs("no JPype (pip install JPype1: the java extra)")
    out = tmp_path_factory.mktemp("mixed")
    shutil.copytree(MODEL.parent / "app", out, dirs_exist_ok=True)
    built = build(MODEL, out)
    assert built.code == 0, built.both
    return out


@pytest.fixture(scope="module")
def registry(out: Path) -> Iterator[ModuleType]:
    sys.path.insert(0, str(out))
    try:
        from mixedgreenhouse_app import registry

        yield registry
    finally:
        sys.path.remove(str(out))
        for name in [m for m in sys.modules if m.split(".")[0] == PACKAGE]:
            del sys.modules[name]


@pytest.fixture
def app(registry: ModuleType):
    with registry.assemble_application() as running:
        yield running


def run(out: Path, container: str, *args: str, **env: str) -> subprocess.CompletedProcess:
    environ = {**os.environ, "PYTHONPATH": str(out), **env}
    return subprocess.run(
        [sys.executable, "-m", f"{PACKAGE}.{container}", *args],
        cwd=out, env=environ, capture_output=True, text=True, timeout=120,
    )  # fmt: skip


def test_python_and_java_components_call_each_other_through_their_ports(app):
    house = app.container("House")
    # Python -> Java (Sensor.AskVentPort -> Vent.report), which calls Java -> Python
    # (Vent.ThermoPort -> Sensor.readTemperature): 16 degrees at t=0.
    said = house.find("Sensor").call("ventReport")
    assert said == "the vent says: opening 0.0 % at 16.0 C after 0 change(s)"
    assert house.find("Vent").call("calibrate", 20.0) == pytest.approx(4.0)
    assert house.stats["calls"] >= 4  # every call went through the container, both ways


def test_the_policy_writes_the_java_components_property_into_its_field(app):
    house = app.container("House")
    changes = []
    house.subscribe(ev.PROPERTY_CHANGED, changes.append, name="t", element="Vent")
    app.clock.run_until(12.0)
    opening = house.get_property("Vent", "opening")
    assert opening > 50  # 34 degrees at t=12: the Ventilation set opens the vent wide
    java = house.find("Vent").instance.java
    assert float(java.getOpening()) == opening  # the Java field holds the container's value
    # the Java onPropertyChanged ran once per change the policy made
    assert house.find("Vent").call("report").endswith(f"after {len(changes)} change(s)")


def test_a_java_setter_changes_the_property_through_the_container(app):
    house = app.container("House")
    seen = []
    house.subscribe(ev.PROPERTY_CHANGED, seen.append, name="t", element="Vent")
    house.find("Vent").instance.java.setOpening(33.0)
    assert house.get_property("Vent", "opening") == 33.0
    assert [(e.attribute, e.value, e.old) for e in seen] == [("opening", 33.0, 0.0)]


def test_notifications_cross_both_ways_through_asynchronous_ports(app):
    house = app.container("House")
    house.find("Sensor").call("notice", "door open")  # Python -> Java: Vent.onMessage
    app.clock.run_until(app.clock.now() + 0.1)  # the receiving port's queue is pumped by the clock
    assert house.find("Vent").call("lastNotice") == "NoticeInPort: door open"
    with pytest.raises(ComponentError):  # Java -> Python: the alarm, then the exception
        house.find("Vent").call("calibrate", -5.0)
    app.clock.run_until(app.clock.now() + 0.1)
    assert house.find("Sensor").call("alarms") == "calibration to -5.0 C refused"


def test_java_code_uses_the_four_rule_engine_calls_over_a_policy_set(app):
    house = app.container("House")
    # Vent.advise: defrule, set, fire, get over the Ventilation set's engine (its own rules,
    # in a rule set named Vent); the oracle: the same rules defined and fired from Python.
    engine = house.policy_set("Ventilation").engine
    for temperature in (10.0, 27.0, 40.0):
        advised = house.find("Vent").call("advise", temperature)
        engine.defrule("py_cool: if temperature is cool then Vent.opening is closed", "oracle")
        engine.defrule("py_hot: if temperature is hot then Vent.opening is wide", "oracle")
        engine.set("temperature", temperature)
        engine.fire("oracle")
        assert advised == pytest.approx(engine.get("Vent.opening"))
    assert (
        house.find("Vent").call("advise", 40.0) > 80 > 20 > house.find("Vent").call("advise", 10.0)
    )


def test_a_replaced_java_component_runs_its_new_code_with_its_properties(app, registry, out,
                                                                         tmp_path):  # fmt: skip
    house = app.container("House")
    ref = house.find("Vent")
    house.remove_policy_set("Ventilation")  # only this test's write changes the opening
    house.set_property("Vent", "opening", 42.0)
    sources = tmp_path / "java"
    shutil.copytree(out / "java", sources)
    user = sources / "mixedgreenhouse" / "Vent.java"
    user.write_text(user.read_text(encoding="utf-8").replace('"opening %.1f', '"v2: opening %.1f'),
                    encoding="utf-8")  # fmt: skip
    descriptor = next(c for c in registry.descriptor().components if c.name == "Vent")
    house.remove_factory("Vent")
    house.install_factory(java_factory(descriptor, "MixedGreenhouse", sources))
    house.replace("Vent", "Vent")
    assert ref.call("report") == "v2: opening 42.0 % at 16.0 C after 0 change(s)"  # same handle
    assert float(ref.instance.java.getOpening()) == 42.0  # the state restored into its field
    assert house.find("Sensor").call("ventReport").startswith("the vent says: v2:")  # its ports
    assert not house.faults.recent


def test_an_update_replaces_a_java_component_whose_java_class_changed(app, out):
    house = app.container("House")
    classes = PackageClasses(PACKAGE)
    loaded = classes.code(["Vent", "Sensor"])
    assert loaded["Vent"]["file"] == "java/mixedgreenhouse/Vent.java"  # what update compares
    assert loaded["Sensor"]["file"] == f"{PACKAGE}/components/Sensor.py"
    descriptor = (out / PACKAGE / "descriptor.xml").read_bytes()
    managed = Management(app, "House", descriptor, classes=classes, code=loaded)
    user = out / "java" / "mixedgreenhouse" / "Vent.java"
    before = user.read_bytes()
    try:
        user.write_bytes(before.replace(b'"opening %.1f', b'"updated: opening %.1f'))
        reply = managed.apply(descriptor.decode(), managed.digest, {}, False, ["Vent"])
        assert reply["status"] == "applied" and reply["applied"] == ["~ code of component Vent"]
        opening = house.get_property("Vent", "opening")
        assert house.find("Vent").call("report").startswith(f"updated: opening {opening:.1f} %")
        assert managed.status()["code"]["Vent"]["sha256"] != loaded["Vent"]["sha256"]
    finally:
        user.write_bytes(before)


def test_a_java_exception_is_a_fault_with_its_java_stack_and_the_container_goes_on(app):
    house = app.container("House")
    with pytest.raises(ComponentError) as raised:
        house.find("Vent").call("calibrate", 80.0)
    assert "java.lang.IllegalArgumentException: reference 80.0 C is outside" in str(raised.value)
    (fault,) = house.faults.recent  # one fault: the alarm it sent first went through
    assert house.faults.counts["component"] == 1 and fault.where == "Vent.calibrate"
    stack = fault.error.splitlines()[1:]
    assert stack and re.fullmatch(
        r"\tat mixedgreenhouse\.Vent\.calibrate\(Vent\.java:\d+\)", stack[0]
    )
    assert not any("jpype" in line or "reflect" in line for line in stack)  # the host's frames
    assert house.find("Vent").call("calibrate", 25.0) == pytest.approx(9.0)  # it goes on


def test_a_python_component_calls_the_java_one_over_pyro5_from_another_process(out: Path):
    token = {"ACORDCS_TOKEN": "java-hosting-test-token"}
    house = subprocess.Popen(
        [sys.executable, "-m", f"{PACKAGE}.House", "--clock", "real", "--serve", "0",
         "--host", "127.0.0.1"],
        cwd=out, env={**os.environ, "PYTHONPATH": str(out), **token},
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert house.stdout is not None
        uri = None
        for line in house.stdout:  # readiness: the line its start script waits for
            if line.startswith("House: serving at "):
                uri = line.split(" at ", 1)[1].strip()
                break
        assert uri, house.stderr.read() if house.stderr else ""
        shed = run(out, "Shed", "--remote", f"House={uri}", "--run", "Panel.show",
                   "--duration", "0", **token)  # fmt: skip
        assert shed.returncode == 0, shed.stdout + shed.stderr
        assert re.search(r"--run Panel\.show\(\) returned 'shed panel: opening [\d.]+ % at "
                         r"[\d.]+ C after \d+ change\(s\)'", shed.stdout), shed.stdout  # fmt: skip
    finally:
        house.terminate()
        house.wait(timeout=30)


def test_a_container_hosting_no_java_component_loads_no_jpype(out: Path):
    code = (
        "import sys; from mixedgreenhouse_app.registry import assemble_application; "
        "assemble_application(only=['Shed'], remote={'House': 'PYRO:x@127.0.0.1:9'}).close(); "
        "print('jpype' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=out, capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(out)}, timeout=60)  # fmt: skip
    assert done.stdout.strip() == "False", done.stdout + done.stderr


def test_a_start_without_javac_names_the_component_and_what_to_install(out: Path, tmp_path):
    unbuilt = tmp_path / "out"  # as built without a JDK: no java-classes/
    shutil.copytree(out, unbuilt, ignore=shutil.ignore_patterns("java-classes"))
    bare = tmp_path / "bin"  # a PATH without javac, and an empty cache: it must compile
    bare.mkdir()
    done = run(unbuilt, "House", "--duration", "1", PATH=str(bare), XDG_CACHE_HOME=str(tmp_path))
    assert done.returncode == 2, done.stdout + done.stderr
    assert "error: component 'Vent' (Vent, id _Vent) tagged language=java" in done.stderr
    assert "no javac is on PATH" in done.stderr and "openjdk-17-jdk-headless" in done.stderr
    assert "Traceback" not in done.stderr


def test_a_java_class_that_does_not_compile_stops_the_start_at_its_line(out: Path, tmp_path):
    broken = tmp_path / "out"
    shutil.copytree(out, broken)
    source = broken / "java" / "mixedgreenhouse" / "Vent.java"
    lines = source.read_text(encoding="utf-8").splitlines()
    at = next(i for i, line in enumerate(lines) if "return reference -" in line)
    lines[at] = lines[at].replace(";", "")
    source.write_text("\n".join(lines) + "\n", encoding="utf-8")
    done = run(broken, "House", "--duration", "1")
    assert done.returncode == 2, done.stdout + done.stderr
    assert f"{source}:{at + 1}: error: component 'Vent' (Vent, id _Vent): its Java class does " \
        "not compile: ';' expected" in done.stderr  # fmt: skip
    assert "Traceback" not in done.stderr


def test_a_throwing_constructor_and_a_call_to_a_missing_port_are_faults(registry, out, tmp_path):
    sources = tmp_path / "java"
    shutil.copytree(out / "java", sources)
    user = sources / "mixedgreenhouse" / "Vent.java"
    text = user.read_text(encoding="utf-8")
    text = text.replace(
        "    public Vent() {\n        super();\n",
        "    private static int made;\n\n"
        "    public Vent() {\n        super();\n        if (made++ > 0) {\n"
        '            throw new IllegalStateException("one vent only");\n        }\n',
    )
    text = text.replace('double temperature = ((Number) ThermoPort.call(',
                        'double temperature = ((Number) port("Nope").call(')  # fmt: skip
    user.write_text(text, encoding="utf-8")
    descriptor = next(c for c in registry.descriptor().components if c.name == "Vent")
    with Container("Test", clock=VirtualClock()) as test:
        test.install_factory(java_factory(descriptor, "MixedGreenhouse", sources))
        vent = test.create("Vent", "Vent")
        with pytest.raises(ComponentError, match="IllegalArgumentException: Vent has no port Nope"):
            vent.call("report")
        with pytest.raises(ComponentError, match="one vent only"):
            test.create("Vent", "Another")
        assert [(f.where, f.context.get("phase")) for f in test.faults.recent] == [
            ("Vent.report", None), ("Another", "create")]  # fmt: skip
        assert vent.call("lastNotice") == ""  # the container and the first vent go on


STREAM = "org.acordcs.runtime.Port.Kind.STREAM, org.acordcs.runtime.Port.Role."
VARIANT = {  # what the variant's Vent.java has instead (method bodies, the constructor)
    "    public Vent() {\n        super();\n": (
        "    public Vent() {\n        super();\n"
        f'        addPort(new org.acordcs.runtime.Port("Readings", {STREAM}PROVIDED));\n'
        f'        addPort(new org.acordcs.runtime.Port("Feed", {STREAM}REQUIRED));\n'
    ),
    "    public java.lang.String report() {": (
        "    public java.lang.String report() {\n"
        "        long spins = 0;\n"
        "        while (!Thread.currentThread().isInterrupted()) {  // forever, but for an interrupt\n"
        "            spins++;\n"
        "        }\n"
        '        return "stopped after " + spins + " spins";\n'
        "    }\n"
    ),
    "    public double advise(double temperature) {": (
        "    public double advise(double temperature) {\n"
        '        port("Readings").push(java.util.List.of(1.5, "two"));\n'
        '        port("Readings").push(3);\n'
        "        return temperature;\n"
        "    }\n"
    ),
}


@pytest.fixture(scope="module")
def variant(out: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The application with a Java vent whose report loops until its thread is interrupted, and
    whose advise pushes two items on a stream port Readings (it consumes one, Feed): compiled
    once, into the cache every test here and the containers they start share."""
    served = tmp_path_factory.mktemp("variant") / "app"
    shutil.copytree(out, served)
    user = served / "java" / "mixedgreenhouse" / "Vent.java"
    text = user.read_text(encoding="utf-8")
    for start, new in VARIANT.items():
        old = text[text.index(start) :]
        old = old[: len(start) if start.endswith("\n") else old.index("    }\n") + 6]
        text = text.replace(old, new)
    user.write_text(text, encoding="utf-8")
    return served


def test_a_java_loop_past_its_calls_timeout_is_interrupted_and_a_fault(registry, variant):
    import jpype

    descriptor = next(c for c in registry.descriptor().components if c.name == "Vent")
    sources = variant / "java"
    with Container("Test", clock=VirtualClock()) as test:
        test.install_factory(java_factory(descriptor, "MixedGreenhouse", sources, timeout=0.2))
        vent = test.create("Vent", "Vent")
        with pytest.raises(ComponentError) as raised:
            vent.call("report")
        assert (
            "Vent.report did not return within its call's timeout of 0.2 s: its Java thread was "
            "interrupted, and it ended with java.lang.InterruptedException" in str(raised.value)
        )
        assert test.faults.counts["component"] == 1
        assert [f.where for f in test.faults.recent] == ["Vent.report"]
        # the thread's interrupt status is cleared, and the container answers the next call
        assert not jpype.JClass("java.lang.Thread").currentThread().isInterrupted()
        assert vent.call("lastNotice") == ""
        assert test.faults.counts["component"] == 1


def test_stream_items_cross_both_ways_through_stream_ports(registry, variant):
    import dataclasses

    from acordcs.descriptor.application import Port as PortDescription
    from acordcs.runtime.component import ComponentFactory, CtxComponent
    from acordcs.runtime.ports import stream_port

    vent = next(c for c in registry.descriptor().components if c.name == "Vent")

    def port(name: str, role: str) -> PortDescription:
        return PortDescription(f"_Vent.{name}", name, f"Vent::{name}", "stream", role)

    vent = dataclasses.replace(
        vent, ports=(*vent.ports, port("Readings", "provided"), port("Feed", "required"))
    )

    class Station(CtxComponent):  # the Python end: consumes Readings, produces Feed
        ports = (stream_port("Readings", "required"), stream_port("Feed", "provided"))
        got: list

        def on_Readings(self, item: object) -> None:
            self.got = [*getattr(self, "got", []), item]

    with Container("Test", clock=VirtualClock()) as test:
        test.install_factory(java_factory(vent, "MixedGreenhouse", variant / "java"))
        test.install_factory(ComponentFactory("Station", Station))
        java = test.create("Vent", "Vent")
        station = test.create("Station", "Station")
        test.connect("Station.Readings", "Vent.Readings")  # Java -> Python
        test.connect("Vent.Feed", "Station.Feed")  # Python -> Java
        assert java.call("advise", 7.0) == 7.0
        assert station.instance.got == [[1.5, "two"], 3]  # Java's List and Integer, as Python's
        assert [type(v) for v in station.instance.got[0]] == [float, str]
        station.instance.port("Feed").push({"t": 20.5})
        assert java.call("lastNotice") == "Feed: {t=20.5}"  # Java's onMessage got a HashMap
        assert not test.faults.recent


def test_a_remote_callers_timeout_fault_and_the_container_answers_again(variant: Path):
    served = variant
    token = {"ACORDCS_TOKEN": "java-timeout-test-token"}
    house = subprocess.Popen(
        [sys.executable, "-m", f"{PACKAGE}.House", "--clock", "real", "--serve", "0",
         "--host", "127.0.0.1", "--timeout", "0.3"],
        cwd=served, env={**os.environ, "PYTHONPATH": str(served), **token},
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert house.stdout is not None
        uri = None
        for line in house.stdout:  # readiness: the line its start script waits for
            if line.startswith("House: serving at "):
                uri = line.split(" at ", 1)[1].strip()
                break
        assert uri, house.stderr.read() if house.stderr else ""
        for _ in range(2):  # the second call: the container answers after the first one's fault
            shed = run(served, "Shed", "--remote", f"House={uri}", "--run", "Panel.show",
                       "--duration", "0", "--timeout", "5", **token)  # fmt: skip
            assert shed.returncode != 0, shed.stdout + shed.stderr
            said = shed.stdout + shed.stderr
            assert "Vent.report did not return within its call's timeout of 0.3 s: its Java " \
                "thread was interrupted" in said, said  # fmt: skip
    finally:
        house.terminate()
        rest, errors = house.communicate(timeout=30)
    assert "faults: 2" in rest, rest + errors  # both counted by the serving container
