"""The metamodel's vocabularies (port kinds and roles, engines, semantics, triggers, languages,
connectors, membership shapes, directions, acquisition kinds) are the same everywhere: in
``acordcs.ecore`` as pyecore reads it (an independent reader), in :mod:`acordcs.vocabularies`,
in the descriptor's schema (written from them, and current), in the profile's tags, in the
runtime's ports, component descriptions, monitors, connectors, engines and policy sets (their
checks and their defaults), in the rule language's term shapes and in the model checks; and the
runtime reads them without the toolchain."""

from __future__ import annotations

import dataclasses
import inspect
import subprocess
import sys

import pytest
from lxml import etree

from acordcs import metamodel, vocabularies
from tests.support.toolchain import ROOT
from tools.write_schema_enumerations import SCHEMA, SIMPLE_TYPES, enumeration_values, schema_text

XS = "{http://www.w3.org/2001/XMLSchema}"


def ecore_literals() -> dict[str, tuple[str, ...]]:
    """Every EEnum of the metamodel as pyecore loads it."""
    from pyecore.ecore import EEnum

    return {
        c.name: tuple(lit.name for lit in c.eLiterals)
        for c in metamodel.load().eClassifiers
        if isinstance(c, EEnum)
    }


def ecore_default(eclass: str, feature: str) -> str:
    """The default value of an enumeration-typed feature, as pyecore reads the metamodel."""
    found = metamodel.eclass(eclass).findEStructuralFeature(feature)
    return found.get_default_value().name


def test_the_leaf_reads_what_pyecore_reads() -> None:
    assert vocabularies.enumerations() == ecore_literals()
    assert metamodel.ecore_path() == vocabularies.ECORE_PATH
    named = {
        "PortKind": vocabularies.PORT_KINDS,
        "PortRole": vocabularies.PORT_ROLES,
        "EngineKind": vocabularies.ENGINES,
        "FuzzySemantics": vocabularies.SEMANTICS,
        "PolicyTrigger": vocabularies.TRIGGERS,
        "ImplementationLanguage": vocabularies.LANGUAGES,
        "ConnectorKind": vocabularies.CONNECTORS,
        "MembershipShape": vocabularies.SHAPES,
        "ParameterDirection": vocabularies.DIRECTIONS,
        "MonitorAcquisition": vocabularies.ACQUISITIONS,
    }
    assert named == ecore_literals()
    with pytest.raises(KeyError, match=r"no EEnum 'PortKinds' in acordcs\.ecore"):
        vocabularies.literals("PortKinds")


# ---------------------------------------------------------------------------------- the schema
def test_the_shipped_schema_is_current() -> None:
    current = SCHEMA.read_text(encoding="utf-8")
    assert schema_text(current) == current, "run python tools/write_schema_enumerations.py"


def test_the_schema_enumerates_every_eenum_of_the_metamodel() -> None:
    schema = etree.parse(str(SCHEMA)).getroot()
    enumerated = {
        t.get("name"): tuple(e.get("value") for e in t.iter(f"{XS}enumeration"))
        for t in schema.iter(f"{XS}simpleType")
        if t.get("name")
    }
    literals = ecore_literals()
    for simple_type, (enum, left_out, _why) in SIMPLE_TYPES.items():
        assert enumerated[simple_type] == enumeration_values(simple_type), simple_type
        assert enumerated[simple_type] == tuple(v for v in literals[enum] if v not in left_out)
    # a new EEnum in the metamodel is a decision for the schema too
    assert {enum for enum, _, _ in SIMPLE_TYPES.values()} == set(literals)


def test_a_descriptor_with_a_value_outside_the_vocabulary_is_refused(tmp_path) -> None:
    from acordcs.descriptor import DescriptorError, from_xml
    from tests.support.generator import build

    assert build(ROOT / "samples/weblab/weblab.xmi", tmp_path, "--target", "config").code == 0
    data = (tmp_path / "WebLab.descriptor.xml").read_bytes()
    assert from_xml(data).name == "WebLab"
    assert b'kind="asynchronous"' in data
    with pytest.raises(DescriptorError, match="'notification' is not an element of the set"):
        from_xml(data.replace(b'kind="asynchronous"', b'kind="notification"', 1))


# ---------------------------------------------------------------------------------- the profile
def test_the_profiles_enumerated_tags_take_the_metamodels_literals() -> None:
    from acordcs.profile import profile

    literals = ecore_literals()
    typed = [(s.name, t) for s in profile() for t in s.tags if t.type in literals]
    assert {t.type for _, t in typed} >= {
        "PortKind",
        "PortRole",
        "EngineKind",
        "FuzzySemantics",
        "PolicyTrigger",
        "ConnectorKind",
        "MonitorAcquisition",
        "ImplementationLanguage",
    }
    for stereotype, tag in typed:
        assert tag.values == literals[tag.type], (stereotype, tag.name)


def test_the_model_checks_know_the_acquisition_kinds() -> None:
    from acordcs.model.queries import ACQUISITIONS

    assert ecore_literals()["MonitorAcquisition"] == ACQUISITIONS


# ---------------------------------------------------------------------------------- the runtime
def test_ports_take_the_metamodels_kinds_roles_and_defaults() -> None:
    from acordcs.runtime.errors import PortError
    from acordcs.runtime.ports import KINDS, ROLES, PortSpec

    literals = ecore_literals()
    assert (literals["PortKind"], literals["PortRole"]) == (KINDS, ROLES)
    defaults = {f.name: f.default for f in dataclasses.fields(PortSpec)}
    assert defaults["kind"] == ecore_default("CtxPort", "kind")
    assert defaults["role"] == ecore_default("CtxPort", "role")
    for kind in literals["PortKind"]:
        assert PortSpec("p", kind).kind == kind
    with pytest.raises(PortError, match="is not one of synchronous, asynchronous, stream"):
        PortSpec("p", "notification")


def test_component_descriptions_take_the_metamodels_port_vocabulary() -> None:
    from acordcs.runtime.repository import PortDescription

    defaults = {f.name: f.default for f in dataclasses.fields(PortDescription)}
    assert defaults["kind"] == ecore_default("CtxPort", "kind")
    assert defaults["role"] == ecore_default("CtxPort", "role")
    # what it accepts and refuses: tests/runtime/test_repository_provider.py


def test_every_acquisition_kind_has_its_monitor_class() -> None:
    from acordcs.runtime.acquisition import MONITOR_KINDS

    assert tuple(MONITOR_KINDS) == ecore_literals()["MonitorAcquisition"]


def test_every_connector_kind_has_its_connector() -> None:
    from acordcs.runtime.connectors import InProcessConnector, RemoteConnector, ShapedConnector

    kinds = (InProcessConnector.kind, RemoteConnector.kind, ShapedConnector.kind)
    assert kinds == ecore_literals()["ConnectorKind"]


def test_every_engine_kind_is_built_in_with_its_rule_syntax() -> None:
    from acordcs.engines import engine_registry as registry
    from acordcs.rules.binding import RULE_SYNTAX

    engines = ecore_literals()["EngineKind"]
    assert tuple(RULE_SYNTAX) == engines
    for engine in engines:
        constructor, syntax, loads_plan = registry.lookup_engine(engine)
        assert callable(constructor) and syntax == RULE_SYNTAX[engine] and loads_plan


def test_policy_sets_take_the_metamodels_semantics_triggers_and_defaults() -> None:
    from acordcs.engines.fuzzy.semantics import PRESETS
    from acordcs.runtime.errors import ConfigurationError
    from acordcs.runtime.policy import PolicySet

    literals = ecore_literals()
    assert set(literals["FuzzySemantics"]) <= set(PRESETS)
    parameters = inspect.signature(PolicySet).parameters
    for feature in ("engine", "trigger", "semantics"):
        assert parameters[feature].default == ecore_default("CtxPolicySet", feature), feature
    for trigger in literals["PolicyTrigger"]:
        assert PolicySet("p", {}, trigger=trigger, frequency=1.0).trigger == trigger
    with pytest.raises(ConfigurationError, match="trigger must be 'event' or 'periodic'"):
        PolicySet("p", {}, trigger="often")


def test_term_shapes_are_the_metamodels() -> None:
    from acordcs.engines.fuzzy.membership import SHAPES, make_membership
    from acordcs.rules import parse_terms

    shapes = ecore_literals()["MembershipShape"]
    assert shapes == SHAPES
    every_form = "a := trape 0 0 1 2; b := trian 0 1 2; c := gauss 1 1; d := gbell 1 2 3;"
    every_form += " e := sigm 1 2; f := (0, 0) (1, 1); g := 3"
    parsed = parse_terms(every_form)
    assert {t.shape for t in parsed} == set(shapes)
    for term in parsed:
        make_membership(term.shape, term.parameters)  # the engine takes every one


def test_the_runtime_reads_the_vocabularies_without_the_toolchain() -> None:
    # A generated application imports the runtime, never acordcs.metamodel (pyecore).
    code = (
        "import sys; import acordcs.runtime.ports, acordcs.runtime.policy, "
        "acordcs.runtime.repository, acordcs.engines.fuzzy; "
        "print(sorted(m for m in sys.modules if m in ('acordcs.metamodel', 'acordcs.profile', "
        "'pyecore') or m.startswith(('acordcs.metamodel.', 'pyecore.'))))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True
    )
    assert done.stdout.strip() == "[]"
