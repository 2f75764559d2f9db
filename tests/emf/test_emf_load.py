"""The metamodel and the model files our toolchain writes load in Eclipse EMF itself.

A small Java program (LoadAcordcs.java, next to this file) is compiled against Debian's EMF jars and
run on ``acordcs.ecore`` and on model instance files written by ``acordcs.metamodel.save_model``
and by ``acordcs-gen export``. It validates the EPackage and every model with EMF's Diagnostician
and prints what EMF read: objects per EClass, every attribute value, every cross reference. The
tests compare that with the pyecore objects that were saved. An exported file is loaded as an EMF
tool opens one: with no metamodel registered, EMF finds ``acordcs.ecore`` by the file's
``xsi:schemaLocation``.

Needs a JDK (javac, java) and the jars of libeclipse-emf-{common,ecore,ecore-xmi}-java. Outside CI
(``CI`` is not ``true``) the tests skip when those are missing; in CI they fail.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from pyecore.ecore import EClass, EEnum

from acordcs import metamodel
from acordcs.metamodel import create, save_model

pytestmark = pytest.mark.service

HERE = Path(__file__).resolve().parent
JAVA_SOURCE = HERE / "LoadAcordcs.java"
PROJECT = HERE.parent.parent
WEBLAB_SAMPLE = PROJECT / "samples" / "weblab" / "weblab.xmi"
SMARTROOM_SAMPLE = PROJECT / "samples" / "smartroom" / "smartroom.xmi"
THERMOSTAT_SAMPLE = PROJECT / "samples" / "papyrus" / "thermostat.uml"
JAR_DIR = Path(os.environ.get("ACORDCS_EMF_JAR_DIR", "/usr/share/java"))
# Debian's unversioned symlinks; the package that provides each, for the error message.
JARS = {
    "eclipse-emf-common.jar": "libeclipse-emf-common-java",
    "eclipse-emf-ecore.jar": "libeclipse-emf-ecore-java",
    "eclipse-emf-ecore-xmi.jar": "libeclipse-emf-ecore-xmi-java",
}
SEP = "\x1f"


def _stem(path: Path) -> str:
    return path.stem


def _unavailable(reason: str) -> None:
    if os.environ.get("CI") == "true":
        pytest.fail(f"EMF load test cannot run in CI: {reason}")
    pytest.skip(f"EMF load test needs a JDK and the EMF jars: {reason}")


@dataclass
class EmfRun:
    returncode: int
    stdout: str
    stderr: str
    counts: dict[str, Counter] = field(default_factory=dict)  # model -> EClass -> n
    attrs: dict[str, dict[tuple[str, str], tuple[bool, str, object]]] = field(default_factory=dict)
    refs: dict[str, dict[tuple[str, str], list[str]]] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    metamodels: dict[str, tuple[str, str]] = field(default_factory=dict)  # model -> nsURI, file

    def explain(self) -> str:
        return f"exit {self.returncode}\nstdout:\n{self.stdout}\nstderr:\n{self.stderr}"


def _unescape(text: str) -> str:
    out, i = [], 0
    while i < len(text):
        c = text[i]
        if c == "\\" and i + 1 < len(text):
            out.append({"t": "\t", "n": "\n", "\\": "\\"}.get(text[i + 1], text[i + 1]))
            i += 2
        else:
            out.append(c)
            i += 1
    return "".join(out)


def _parse(proc: subprocess.CompletedProcess) -> EmfRun:
    run = EmfRun(proc.returncode, proc.stdout, proc.stderr)
    for line in proc.stdout.splitlines():
        kind, *rest = line.split("\t")
        if kind == "count":
            model, eclass, n = rest
            run.counts.setdefault(model, Counter())[eclass] = int(n)
        elif kind == "attr":
            model, frag, feature, is_set, vkind, value = rest
            value = _unescape(value)
            parsed: object = value
            if vkind == "null":
                parsed = None
            elif vkind == "many":
                parsed = value.split(SEP) if value else []
            run.attrs.setdefault(model, {})[frag, feature] = (is_set == "true", vkind, parsed)
        elif kind == "ref":
            model, frag, feature, targets = rest
            targets = _unescape(targets)
            run.refs.setdefault(model, {})[frag, feature] = targets.split(SEP) if targets else []
        elif kind == "problem":
            run.problems.append("\t".join(rest))
        elif kind == "metamodel":
            model, ns_uri, location = rest
            run.metamodels[model] = (ns_uri, location)
    return run


@pytest.fixture(scope="session")
def emf(tmp_path_factory):
    """A function running LoadAcordcs on the metamodel and the given model files."""
    javac, java = shutil.which("javac"), shutil.which("java")
    if not javac or not java:
        _unavailable("javac/java not on PATH; install openjdk-17-jdk-headless")
    missing = [
        f"{JAR_DIR / jar} (Debian package {pkg})"
        for jar, pkg in JARS.items()
        if not (JAR_DIR / jar).is_file()
    ]
    if missing:
        _unavailable("missing " + ", ".join(missing) + "; run `make system-packages` as root")
    classpath = os.pathsep.join(str(JAR_DIR / jar) for jar in JARS)
    classes = tmp_path_factory.mktemp("emf-classes")
    compiled = subprocess.run(
        [javac, "-Xlint:all", "-Werror", "-d", str(classes), "-cp", classpath, str(JAVA_SOURCE)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert compiled.returncode == 0, f"javac failed on {JAVA_SOURCE}:\n{compiled.stderr}"

    def run(*models: Path, by_schema_location: bool = False) -> EmfRun:
        """LoadAcordcs on ``models``, with our metamodel registered, or (``by_schema_location``)
        with none: EMF loads the one each model names."""
        first = "--by-schema-location" if by_schema_location else metamodel.ecore_path()
        proc = subprocess.run(
            [
                java,
                "-cp",
                os.pathsep.join([str(classes), classpath]),
                "LoadAcordcs",
                first,
                *map(str, models),
            ],
            capture_output=True,
            text=True,
            timeout=300,
        )
        return _parse(proc)

    return run


# --- the model covering every EClass and every EEnum literal -------------------------------------


def _literal(enum: str, name: str):
    found = metamodel.load().getEClassifier(enum).getEEnumLiteral(name)
    assert found is not None, f"EEnum {enum} has no literal {name!r}"
    return found


def covering_model():
    """An Application with at least one instance of every concrete EClass and every literal of
    every EEnum, with every reference and every kind of attribute set."""
    lit = _literal
    ops = []
    for n, direction in enumerate(("in", "out", "inout", "return")):
        ops.append(
            create(
                "Parameter",
                name=f"p{n}",
                type="int",
                direction=lit("ParameterDirection", direction),
            )
        )
    shapes = {
        "trapezoid": [0.0, 0.0, 40.0, 80.0],
        "triangle": [60.0, 200.0, 200.0],
        "gaussian": [100.0, 12.5],
        "bell": [50.0, 2.0, 100.0],
        "sigmoid": [0.25, 150.0],
        "points": [0.0, 0.0, 10.0, 1.0, 20.0, 0.0],
        "singleton": [1e-4],
    }
    terms = [
        create(
            "LinguisticTerm", name=f"t_{shape}", shape=lit("MembershipShape", shape), parameters=p
        )
        for shape, p in shapes.items()
    ]
    speed = create(
        "Attribute",
        name="speed",
        type="double",
        defaultValue="0",
        xmiId="BOUML_0x1f402_1",
        sourceLine=42,
        variable=create("CtxVariable", rangeMin=-1.5, rangeMax=200.0, terms=terms),
    )
    retries = create("Attribute", name="retries", type="int", defaultValue="0")
    locomotion = create(
        "CtxComponent",
        name="Locomotion",
        language=lit("ImplementationLanguage", "java"),
        attributes=[speed, retries],
        operations=[create("Operation", name="recover", returnType="bool", parameters=ops)],
        ports=[
            create(
                "CtxPort",
                name="drive",
                kind=lit("PortKind", "synchronous"),
                role=lit("PortRole", "provided"),
            ),
            create(
                "CtxPort",
                name="events",
                kind=lit("PortKind", "asynchronous"),
                role=lit("PortRole", "required"),
            ),
            create("CtxPort", name="video", kind=lit("PortKind", "stream")),
        ],
    )
    navigator = create(
        "CtxComponent",
        name="Navigator",
        language=lit("ImplementationLanguage", "python"),
        ports=[create("CtxPort", name="driveClient", role=lit("PortRole", "required"))],
    )
    connections = [
        create(
            "CtxPortConnection",
            name=f"c_{kind}",
            connector=lit("ConnectorKind", kind),
            provided=locomotion.ports[0],
            required=navigator.ports[0],
            attributes=[create("Attribute", name="latency", type="double")],
        )
        for kind in ("inprocess", "remote", "shaped")
    ]
    rules = [
        create(
            "Rule",
            name="slow1",
            label="slow1",
            text="if speed is t_trapezoid\tand retries is t_triangle then speed is t_bell",
            engine=lit("EngineKind", "fuzzy"),
            tag="Rule",
        ),
        create(
            "Rule",
            name="retry",
            text="if Locomotion.speed == 0 and retries < 3 then Locomotion.recover()\n# é ü <&>",
            engine=lit("EngineKind", "clips"),
            tag="RuleRecover",
        ),
    ]
    fuzzy = create(
        "CtxPolicySet",
        name="SpeedLimiting",
        engine=lit("EngineKind", "fuzzy"),
        semantics=lit("FuzzySemantics", "sazonov"),
        trigger=lit("PolicyTrigger", "event"),
        policies=[create("CtxPolicy", name="SlowDown", rules=rules[:1])],
    )
    crisp = create(
        "CtxPolicySet",
        name="Recovering",
        engine=lit("EngineKind", "clips"),
        semantics=lit("FuzzySemantics", "mamdani"),
        trigger=lit("PolicyTrigger", "periodic"),
        frequency=2.5,
        policies=[create("CtxPolicy", name="Recover", rules=rules[1:])],
    )
    user_side = create("CtxContainer", name="UserSide", host="client.example", port=47011)
    lab_side = create("CtxContainer", name="WebLabSide", host="localhost")
    fuzzy.adapts.extend([locomotion, locomotion.ports[2], connections[1], lab_side])
    crisp.adapts.append(locomotion)
    control = create(
        "CtxMonitor",
        name="Control",
        frequency=10.0,
        acquisition=lit("MonitorAcquisition", "custom"),
        sources=[locomotion, locomotion.ports[1]],
        feeds=[fuzzy, crisp],
        attributes=[create("Attribute", name="cycleRate", type="double")],
    )
    usage = create("CtxMonitor", name="Usage", sources=[user_side], feeds=[fuzzy])
    # The other acquisition kinds, each with the tag it needs.
    tapping = create(
        "CtxMonitor",
        name="Tap",
        acquisition=lit("MonitorAcquisition", "intercept"),
        sources=[locomotion.ports[1]],
        feeds=[crisp],
    )
    telemetry = create(
        "CtxMonitor",
        name="Telemetry",
        acquisition=lit("MonitorAcquisition", "subscribe"),
        xpath="/telemetry",
        feeds=[crisp],
    )
    polling = create(
        "CtxMonitor",
        name="Poll",
        acquisition=lit("MonitorAcquisition", "poll"),
        frequency=1.0,
        operation="odometry",
        sources=[locomotion],
        feeds=[fuzzy],
    )
    user_side.components.append(navigator)
    lab_side.components.append(locomotion)
    lab_side.monitors.extend([control, usage, tapping, telemetry, polling])
    lab_side.policySets.extend([fuzzy, crisp])
    return create(
        "Application",
        name="CoverAll",
        containers=[user_side, lab_side],
        components=[navigator, locomotion],
        monitors=[control, usage, tapping, telemetry, polling],
        policySets=[fuzzy, crisp],
        connections=connections,
    )


# --- what pyecore holds, in the terms LoadAcordcs prints -----------------------------------------


def _walk(root):
    """(fragment, object) for the root and everything it contains, as EMF names fragments."""
    out = [("/", root)]

    def visit(obj, frag):
        for ref in obj.eClass.eAllReferences():
            if not ref.containment:
                continue
            value = getattr(obj, ref.name)
            if ref.many:
                for i, child in enumerate(value):
                    child_frag = f"{frag}/@{ref.name}.{i}"
                    out.append((child_frag, child))
                    visit(child, child_frag)
            elif value is not None:
                child_frag = f"{frag}/@{ref.name}"
                out.append((child_frag, value))
                visit(value, child_frag)

    visit(root, "/")
    return out


def _counts(root) -> Counter:
    return Counter(obj.eClass.name for _, obj in _walk(root))


def _same_value(etype, emf_text: str, py_value) -> bool:
    if isinstance(etype, EEnum):
        return emf_text == py_value.name
    name = etype.name
    if name in {"EDouble", "EFloat"}:
        return math.isclose(float(emf_text), float(py_value), rel_tol=1e-15, abs_tol=0.0)
    if name in {"EInt", "ELong", "EShort"}:
        return int(emf_text) == int(py_value)
    if name == "EBoolean":
        return emf_text == ("true" if py_value else "false")
    return emf_text == py_value


def _compare(root, run: EmfRun, model: Path) -> list[str]:
    """Every difference between the pyecore objects and what EMF read."""
    key = str(model)
    diffs = []
    attrs = run.attrs.get(key, {})
    refs = run.refs.get(key, {})
    frag_of = {id(obj): frag for frag, obj in _walk(root)}
    for frag, obj in _walk(root):
        where = f"{obj.eClass.name} at {frag}"
        for attr in obj.eClass.eAllAttributes():
            got = attrs.get((frag, attr.name))
            if got is None:
                diffs.append(f"{where}: EMF printed no value for {attr.name}")
                continue
            is_set, vkind, value = got
            py_value = getattr(obj, attr.name)
            if attr.unsettable and is_set != obj.eIsSet(attr.name):
                diffs.append(
                    f"{where}.{attr.name}: set in pyecore={obj.eIsSet(attr.name)}, in EMF={is_set}"
                )
            if attr.many:
                py_list = list(py_value)
                if len(value) != len(py_list) or not all(
                    _same_value(attr.eType, a, b) for a, b in zip(value, py_list, strict=False)
                ):
                    diffs.append(f"{where}.{attr.name}: pyecore {py_list!r}, EMF {value!r}")
            elif py_value is None or vkind == "null":
                if not (py_value is None and vkind == "null"):
                    diffs.append(f"{where}.{attr.name}: pyecore {py_value!r}, EMF {value!r}")
            elif not _same_value(attr.eType, value, py_value):
                diffs.append(f"{where}.{attr.name}: pyecore {py_value!r}, EMF {value!r}")
        for ref in obj.eClass.eAllReferences():
            if ref.containment or (ref.eOpposite is not None and ref.eOpposite.containment):
                continue
            value = getattr(obj, ref.name)
            targets = list(value) if ref.many else ([] if value is None else [value])
            expected = [frag_of.get(id(t), f"<outside the model: {t!r}>") for t in targets]
            got_refs = refs.get((frag, ref.name))
            if got_refs != expected:
                diffs.append(f"{where}.{ref.name}: pyecore -> {expected}, EMF -> {got_refs}")
    return diffs


def _save(root, path: Path) -> Path:
    save_model(root, str(path))
    return path


# --- tests ---------------------------------------------------------------------------------------


def test_covering_model_covers_every_eclass_and_eenum_literal():
    root = covering_model()
    package = metamodel.load()
    counts = _counts(root)
    concrete = [c for c in package.eClassifiers if isinstance(c, EClass) and not c.abstract]
    missing = [c.name for c in concrete if counts[c.name] == 0]
    assert not missing, f"covering_model() has no instance of {missing}: add one"
    abstract = [c for c in package.eClassifiers if isinstance(c, EClass) and c.abstract]
    for c in abstract:
        assert any(c in obj.eClass.eAllSuperTypes() for _, obj in _walk(root)), (
            f"no instance of a subclass of abstract {c.name} in covering_model(): add one"
        )
    used: set[tuple[str, str]] = set()
    for _, obj in _walk(root):
        for attr in obj.eClass.eAllAttributes():
            if isinstance(attr.eType, EEnum) and obj.eIsSet(attr.name):
                used.add((attr.eType.name, getattr(obj, attr.name).name))
    for enum in (c for c in package.eClassifiers if isinstance(c, EEnum)):
        unused = [lit.name for lit in enum.eLiterals if (enum.name, lit.name) not in used]
        assert not unused, f"covering_model() never sets {enum.name} to {unused}: use them"


def test_metamodel_passes_emf_validation(emf):
    run = emf()
    assert run.returncode == 0, "EMF rejects acordcs.ecore:\n" + run.explain()
    assert not run.problems, "\n".join(run.problems)
    assert "epackage\tacordcs\t" + metamodel.NS_URI in run.stdout, run.explain()


def test_covering_model_loads_in_emf_as_saved(emf, tmp_path):
    root = covering_model()
    path = _save(root, tmp_path / "cover-all.xmi")
    run = emf(path)
    assert run.returncode == 0, f"EMF reports problems in {path}:\n" + run.explain()
    assert run.counts.get(str(path)) == _counts(root), run.explain()
    diffs = _compare(root, run, path)
    assert not diffs, "EMF read something else than pyecore saved:\n" + "\n".join(diffs)


def test_emf_reports_an_invalid_model(emf, tmp_path):
    # NamedElement.name has lowerBound 1: EMF's Diagnostician must refuse a nameless container,
    # which shows the program really fails on what it is there to catch.
    root = create("Application", name="Broken", containers=[create("CtxContainer")])
    path = _save(root, tmp_path / "broken.xmi")
    run = emf(path)
    assert run.returncode == 1, run.explain()
    assert any("ERROR" in p and "name" in p for p in run.problems), run.explain()


def test_emf_reports_a_dangling_reference(emf, tmp_path):
    path = tmp_path / "dangling.xmi"
    _save(covering_model(), path)
    text = path.read_text(encoding="utf-8")
    assert 'feeds="' in text, "the saved covering model has no feeds reference to break"
    path.write_text(text.replace('feeds="', 'feeds="//@nowhere.7 ', 1), encoding="utf-8")
    run = emf(path)
    assert run.returncode != 0, run.explain()


def test_unsettable_attribute_set_to_zero_survives(emf, tmp_path):
    root = create(
        "Application", name="Zero", monitors=[create("CtxMonitor", name="M", frequency=0.0)]
    )
    path = _save(root, tmp_path / "zero.xmi")
    run = emf(path)
    assert run.returncode == 0, run.explain()
    assert not _compare(root, run, path)


def test_weblab_sample_loads_in_emf(emf, tmp_path):
    # The ACORD-CS model read from the WebLab sample, saved by our toolchain, must load in EMF too.
    from acordcs.model.ecore_builder import to_ecore
    from acordcs.model.reading import read_model

    reading = read_model(str(WEBLAB_SAMPLE))
    assert not reading.diagnostics, [d.format_text() for d in reading.diagnostics]
    root = to_ecore(reading.architecture)
    assert root.eClass.name == "Application"
    assert len(root.components) == 6 and len(root.policySets) == 3
    path = _save(root, tmp_path / "weblab.xmi")
    run = emf(path)
    assert run.returncode == 0, f"EMF reports problems in the saved WebLab model:\n{run.explain()}"
    assert run.counts.get(str(path)) == _counts(root), run.explain()
    diffs = _compare(root, run, path)
    assert not diffs, "EMF read something else than pyecore saved:\n" + "\n".join(diffs)


@pytest.mark.parametrize("sample", [WEBLAB_SAMPLE, SMARTROOM_SAMPLE, THERMOSTAT_SAMPLE], ids=_stem)
def test_exported_model_loads_in_emf_by_its_schema_location(emf, tmp_path, sample):
    # What a modeller gets from `acordcs-gen export`: EMF, with nothing registered, loads the
    # metamodel written beside the file and reads back every object, value and reference.
    from acordcs.model.ecore_builder import to_ecore
    from acordcs.model.reading import read_model
    from tests.support.toolchain import run_main

    path = tmp_path / "out" / f"{sample.stem}.acordcs.xmi"
    done = run_main(["export", str(sample), "-o", str(path)])
    assert done.code == 0, done.both
    run = emf(path, by_schema_location=True)
    assert run.returncode == 0, f"EMF reports problems in {path}:\n{run.explain()}"
    beside = tmp_path / "out" / "acordcs.ecore"
    assert run.metamodels[str(path)] == (metamodel.NS_URI, str(beside)), run.explain()
    root = to_ecore(read_model(str(sample)).architecture)
    assert run.counts.get(str(path)) == _counts(root), run.explain()
    diffs = _compare(root, run, path)
    assert not diffs, "EMF read something else than the export wrote:\n" + "\n".join(diffs)


def test_emf_fails_on_an_export_without_its_metamodel(emf, tmp_path):
    # The test above could pass with the metamodel found elsewhere: without the file beside it,
    # EMF must not load the model.
    from tests.support.toolchain import run_main

    path = tmp_path / "weblab.acordcs.xmi"
    assert run_main(["export", str(WEBLAB_SAMPLE), "-o", str(path)]).code == 0
    (tmp_path / "acordcs.ecore").unlink()
    run = emf(path, by_schema_location=True)
    assert run.returncode != 0, run.explain()
