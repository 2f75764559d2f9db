"""The Papyrus samples (``samples/papyrus/*.uml``): each validates with no finding at all, builds
with every target, applies the shipped profile as Papyrus does (each stereotype application an
instance of the profile's Ecore definition, loaded with pyecore), and reads its ports as ports only.
The ventilation sample holds what its README section says: two containers on two hosts, a remote
connection between two ``uml:Port``s across them, a fuzzy and a CLIPS policy set, monitors."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from lxml import etree

from acordcs.generator import build
from acordcs.generator.describe import describe
from acordcs.generator.targets import targets
from acordcs.model.reading import read_model
from acordcs.profile.declaration import PROFILE_URI
from tests.profile.test_papyrus_definition import ID, NS, _load_with_pyecore
from tests.support.toolchain import ROOT, run_main

PAPYRUS = ROOT / "samples" / "papyrus"
SAMPLES = sorted(p for p in PAPYRUS.glob("*.uml") if p.name != "ACORDCS.profile.uml")
VENTILATION = PAPYRUS / "ventilation.uml"


def test_both_samples_are_there() -> None:
    assert [p.name for p in SAMPLES] == ["thermostat.uml", "ventilation.uml"]


@pytest.mark.parametrize("sample", SAMPLES, ids=lambda p: p.name)
def test_the_sample_validates_with_no_finding(sample: Path) -> None:
    result = run_main(["validate", "--fail-on", "warning", str(sample)])
    assert (result.code, result.out) == (0, f"{sample}: 0 errors, 0 warnings, 0 infos\n")


@pytest.mark.parametrize("sample", SAMPLES, ids=lambda p: p.name)
def test_the_sample_builds_with_every_target(sample: Path, tmp_path: Path) -> None:
    result = run_main(["build", "-q", str(sample), "-o", str(tmp_path / "out")])
    assert result.code == 0, result.both
    assert f"(targets: {', '.join(sorted(targets()))})" in result.out


@pytest.mark.parametrize("sample", SAMPLES, ids=lambda p: p.name)
def test_a_uml_port_is_a_port_of_its_component_and_no_property(sample: Path) -> None:
    root = etree.parse(str(sample)).getroot()
    written = {
        port.get(ID): port.getparent().get("name")
        for port in root.iter("ownedAttribute")
        if port.get("{http://www.omg.org/spec/XMI/20131001}type") == "uml:Port"
    }
    assert written, "the sample models its ports as uml:Port"
    app = describe(read_model(str(sample)).architecture)
    ports = {p.id: c.name for c in app.components for p in c.ports}
    assert ports == written
    for component in app.components:
        assert not {p.id for p in component.properties} & set(written), component.name


@pytest.mark.parametrize("sample", SAMPLES, ids=lambda p: p.name)
def test_every_application_is_an_instance_of_the_profile_definition(sample: Path, tmp_path):
    root = etree.parse(str(sample)).getroot()
    loaded = _load_with_pyecore(tmp_path)
    ids = {el.get(ID) for el in root.iter() if el.get(ID)}
    applications = [el for el in root if etree.QName(el).namespace == PROFILE_URI]
    assert applications
    for app in applications:
        eclass = loaded.getEClassifier(etree.QName(app).localname)
        assert eclass is not None, etree.QName(app).localname
        instance = eclass()
        for key, value in app.attrib.items():
            if key == ID:
                continue
            feature = eclass.findEStructuralFeature(key)
            assert feature is not None, f"{eclass.name} has no feature {key}"
            if key.startswith("base_"):
                assert value in ids
            elif hasattr(feature.eType, "getEEnumLiteral"):
                instance.eSet(feature, feature.eType.getEEnumLiteral(value))
                assert instance.eGet(feature).name == value
            elif feature.eType.name in ("Real", "Integer"):
                float(value)
    assert root.xpath("uml:Model/profileApplication/appliedProfile/@href", namespaces=NS) == [
        "ACORDCS.profile.uml#_ACORDCS"
    ]


def test_ventilation_runs_on_two_hosts_with_a_remote_port_connection(tmp_path: Path) -> None:
    app = describe(read_model(str(VENTILATION)).architecture)
    where = {c.name: (c.host, c.endpoint.port if c.endpoint else None) for c in app.containers}
    assert where == {"Plant": ("plant.local", 9101), "Office": ("office.local", 9102)}
    hosted = {c.name: {r.name for r in c.hosts} for c in app.containers}
    assert hosted == {
        "Plant": {"Fan", "AirSensor", "FanWatch", "Airflow", "Upkeep"},
        "Office": {"Panel", "Occupancy"},
    }
    (link,) = app.connections
    assert (link.name, link.connector) == ("FanLink", "remote")
    assert (link.required.component, link.required.port) == ("Panel", "PanelPort")
    assert (link.provided.component, link.provided.port) == ("Fan", "FanPort")
    assert {c.name: c.reaches for c in app.containers} == {"Plant": (), "Office": ("Plant",)}
    assert {p.name: p.engine for p in app.policy_sets} == {"Airflow": "fuzzy", "Upkeep": "clips"}
    assert {m.name: m.acquisition for m in app.monitors} == {
        "AirSensor": "custom",
        "Occupancy": "poll",
        "FanWatch": "intercept",
    }
    result = build(VENTILATION, tmp_path / "out", write=False)
    start = next(c for c in result.plan.changes if c.path == "bin/Office-start")
    assert "--remote 'Plant=PYRO:acordcs.container.Plant@'" in start.new.decode()


def test_the_readme_table_names_the_model_s_elements() -> None:
    readme = (PAPYRUS / "README.md").read_text(encoding="utf-8")
    section = readme.split("# Papyrus sample: the ventilation", 1)[1]
    named = set(re.findall(r"^\| `(\w+)` \| (Ctx\w+)", section, flags=re.M))
    arch = read_model(str(VENTILATION)).architecture
    roles = {
        (r.name, r.kind)
        for r in arch.roles.values()
        if r.kind not in ("CtxPort", "CtxPolicy", "CtxVariable")
    }
    assert named == roles


def test_the_modelling_page_shows_the_port_path_as_it_works(tmp_path: Path, monkeypatch) -> None:
    """docs/modelling.md's Papyrus port: its XMI lines are the sample's, its transcript is what
    validate and build print, its descriptor excerpts are the built descriptor's."""
    page = (ROOT / "docs" / "modelling.md").read_text(encoding="utf-8")
    section = page.split("## A port in Papyrus", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"^```(\w*)\n(.*?)^```", section, flags=re.M | re.S)
    sample = VENTILATION.read_text(encoding="utf-8")
    xmi, transcript, component, connection = blocks
    for line in xmi[1].splitlines():
        if line.strip() != "...":
            assert line.strip() in sample, line
    monkeypatch.chdir(tmp_path)
    (tmp_path / "samples").symlink_to(ROOT / "samples")
    lines = transcript[1].splitlines()
    for n, line in enumerate(lines):
        if line.startswith("$ acordcs-gen "):
            shown = []
            for after in lines[n + 1 :]:
                if after.startswith("$ "):
                    break
                shown.append(after)
            result = run_main(line.split()[2:])
            assert (result.code, result.out.splitlines()) == (0, shown), line
    descriptor = (tmp_path / "build" / "ventilation" / "Ventilation.descriptor.xml").read_text()
    for excerpt in (component[1], connection[1]):
        assert excerpt in descriptor, excerpt
