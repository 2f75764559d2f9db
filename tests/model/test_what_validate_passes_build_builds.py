"""What ``validate`` passes, ``build`` builds, with every built-in target; what ``build`` refuses,
``validate`` refuses with the same codes and exit code.

A differential test over every model file the repository holds (found by globbing ``samples/`` and
``tests/`` for ``*.xmi`` and ``*.uml``, never listed by hand), the hostile corpus of the reader tests
(``tests/xmi/test_hostile_input.py``'s cases, the dialect bases of
``tests/xmi/test_hostile_dialects.py`` and their hostile shapes), and generated variants of one
application (:mod:`tests.support.port_models`): ports as ``uml:Port`` and as ``<<CtxPort>>``
classes, in the Papyrus and the BOUML forms, on one container or two, with each connector; and the
mistakes validate must refuse (an in-process connection between two containers, A516; a joined port
of no component, A517; a port named like an attribute of its component, N603).

For each, in this process: ``acordcs-gen validate MODEL``, and :func:`acordcs.generator.build` with
every target (what ``acordcs-gen build MODEL -o DIR`` runs; in memory, nothing written). Either
validate exits 0 and build succeeds, or build refuses with validate's exit code (1 findings, 2
unreadable) and validate's errors. A built
model's descriptor never holds a property named like a port of the same component (the Papyrus port
read as a port and as a property: issue 30).
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from acordcs.diagnostics import Severity
from acordcs.generator import BuildError, build
from acordcs.generator.targets import targets
from tests.support import port_models
from tests.support.toolchain import ROOT, no_crash, run_main
from tests.xmi import test_hostile_dialects as dialects
from tests.xmi import test_hostile_input as hostile

PROFILE = ROOT / "samples" / "papyrus" / "ACORDCS.profile.uml"
_ERROR = re.compile(r": error: ([A-Z]\d{3}) ")


def _model_files() -> list[Path]:
    found = set()
    for top in ("samples", "tests"):
        for pattern in ("*.xmi", "*.uml"):
            found.update(p for p in (ROOT / top).rglob(pattern) if ".venv" not in p.parts)
    return sorted(found)


MODEL_FILES = _model_files()
VARIANTS = port_models.variants()
# Models the repository holds that must build (the others are its samples of mistakes).
MUST_BUILD = {p for p in MODEL_FILES if "mistakes" not in p.parts}


def assert_validate_and_build_agree(model: Path, out: Path) -> tuple[int, set[str]]:
    """validate and build ``model``; the exit code (the same for both, asserted) and validate's
    error codes."""
    checked = run_main(["validate", str(model)])
    no_crash(checked)
    errors = set(_ERROR.findall(checked.out))
    try:
        result = build(model, out, write=False)  # every target, in memory
    except BuildError as err:
        assert checked.code != 0, (
            f"validate passed {model.name} ({checked.out.splitlines()[-1]}) but build failed: "
            f"{err}\n" + "\n".join(d.format_text() for d in err.diagnostics)
        )
        assert err.exit_code == checked.code, (checked.out, str(err))
        refused = {d.code for d in err.diagnostics if d.severity is Severity.ERROR}
        assert refused == errors, (checked.out, str(err))
        assert not out.exists()
        return checked.code, errors
    assert checked.code == 0, f"build built {model.name}, which validate refuses:\n{checked.out}"
    assert result.targets == sorted(targets()) and result.plan is not None
    _no_port_is_a_property(model)
    return checked.code, errors


def _no_port_is_a_property(model: Path) -> None:
    from acordcs.generator.describe import describe
    from acordcs.model.reading import read_model

    reading = read_model(str(model))
    for component in describe(reading.architecture).components:
        ports = {p.name for p in component.ports}
        both = ports & {p.name for p in component.properties}
        assert not both, f"{model.name}: {component.name}'s ports {sorted(both)} are properties too"


def test_the_repository_holds_the_models_this_test_reads() -> None:
    names = {p.relative_to(ROOT).as_posix() for p in MODEL_FILES}
    assert {
        "samples/papyrus/thermostat.uml",
        "samples/papyrus/ventilation.uml",
        "samples/weblab/weblab.xmi",
        "samples/mistakes/typos.xmi",
        "tests/xmi/tool_models/acordcs_enterprise_architect.xmi",
    } <= names, names


@pytest.mark.parametrize("model", MODEL_FILES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_model_file_of_the_repository(model: Path, tmp_path: Path) -> None:
    code, errors = assert_validate_and_build_agree(model, tmp_path / "out")
    if model in MUST_BUILD:
        assert code == 0, errors


@pytest.mark.parametrize("case", hostile.CASES, ids=[c.id for c in hostile.CASES])
def test_the_hostile_corpus(case, tmp_path: Path) -> None:
    model = hostile.path_for(case, tmp_path)
    assert_validate_and_build_agree(model, tmp_path / "out")


@pytest.mark.parametrize("base", sorted(dialects.BASES))
@pytest.mark.parametrize("shape", [None, *sorted(dialects.SHAPES)])
def test_the_hostile_dialects(base: str, shape: str | None, tmp_path: Path) -> None:
    text = dialects.BASES[base]
    if shape is not None:
        text = dialects.SHAPES[shape][0](text, tmp_path)
    model = tmp_path / "model.xmi"
    model.write_bytes(text.encode(dialects.encoding_of(text), errors="replace"))
    assert_validate_and_build_agree(model, tmp_path / "out")


@pytest.mark.parametrize("spec", VARIANTS, ids=[s.id for s in VARIANTS])
def test_generated_variants(spec: port_models.Spec, tmp_path: Path) -> None:
    model = tmp_path / f"ventilation{spec.suffix}"
    model.write_bytes(port_models.document(spec))
    if spec.file_form == "papyrus":  # beside the model, as Papyrus needs it (else T321)
        shutil.copy(PROFILE, tmp_path / PROFILE.name)
    code, errors = assert_validate_and_build_agree(model, tmp_path / "out")
    if spec.refused_with is None:
        checked = run_main(["validate", str(model)])
        assert code == 0 and " 0 errors, 0 warnings" in checked.out, checked.out
    else:
        assert code == 1 and spec.refused_with in errors, errors


def test_the_variants_cover_each_form() -> None:
    built = [s for s in VARIANTS if s.refused_with is None]
    assert {(s.file_form, s.port_form) for s in built} == {
        (f, p) for f in port_models.FILE_FORMS for p in port_models.PORT_FORMS
    }
    assert {s.connector for s in built} == set(port_models.CONNECTORS)
    assert {s.engine for s in built} == set(port_models.ENGINES)
    assert {s.two_containers for s in built} == {False, True}
    assert {s.refused_with for s in VARIANTS} == {None, "A516", "A517", "N603"}
