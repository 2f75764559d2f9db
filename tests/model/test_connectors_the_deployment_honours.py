"""``validate`` refuses a port connection the deployment cannot honour: an ``inprocess`` connection
between components of two containers (A516; each container runs in a process of its own), and a
connection joining a port that belongs to no component (A517: the descriptor names every end as a
component's port); and a port named like an attribute of its component (N603: the Java class would
have two fields of that name). Each is located (file:line:col, element) and says what to do; the
docs' examples are this output."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from tests.support import port_models
from tests.support.toolchain import ROOT, codes_in, no_crash, replace, run_main

VENTILATION = ROOT / "samples" / "papyrus" / "ventilation.uml"
PROFILE = VENTILATION.parent / "ACORDCS.profile.uml"
CONNECTION = '<ACORDCS:CtxPortConnection xmi:id="_FanLink.app" base_Class="_FanLink"'


def _ventilation(tmp_path: Path, *edits: tuple[str, str]) -> Path:
    text = VENTILATION.read_text(encoding="utf-8")
    for old, new in edits:
        text = replace(text, old, new)
    model = tmp_path / "ventilation.uml"
    model.write_text(text, encoding="utf-8")
    shutil.copy(PROFILE, tmp_path / PROFILE.name)
    return model


def _line_of(model: Path, text: str) -> int:
    lines = model.read_text(encoding="utf-8").splitlines()
    return next(n for n, line in enumerate(lines, start=1) if text in line)


@pytest.mark.parametrize(
    ("edit", "says"),
    [
        (('connector="remote"', 'connector="inprocess"'), "its tag connector is 'inprocess'"),
        ((' connector="remote"', ""), "its tag connector is unset, which means 'inprocess'"),
    ],
    ids=["inprocess", "unset"],
)
def test_an_in_process_connection_between_two_containers_is_refused(
    tmp_path: Path, monkeypatch, edit: tuple[str, str], says: str
) -> None:
    model = _ventilation(tmp_path, edit)
    monkeypatch.chdir(tmp_path)
    result = run_main(["validate", model.name])
    no_crash(result)
    assert result.code == 1 and codes_in(result.out) == {"A516"}, result.out
    (line,) = result.out.splitlines()[:-1]
    assert line == (
        f"ventilation.uml:{_line_of(model, CONNECTION)}:1: error: A516 port connection 'FanLink' "
        f"is in-process ({says}) but joins Panel.PanelPort (container 'Office', host "
        "'office.local') and Fan.FanPort (container 'Plant', host 'plant.local'): each container "
        "runs in a process of its own, which an in-process call cannot leave; set the tag "
        "connector to remote (or shaped), or deploy both components in one container "
        "[Components::FanLink (_FanLink)]"
    )
    built = run_main(["build", model.name, "-o", str(tmp_path / "out")])
    assert built.code == 1 and line in built.out.splitlines()


@pytest.mark.parametrize(
    "edit",
    [
        ('connector="remote"', 'connector="shaped"'),  # over the endpoints, as remote
        ('client="_Office" supplier="_Panel"', 'client="_Plant" supplier="_Panel"'),  # one process
    ],
    ids=["shaped-between-two-containers", "inprocess-in-one-container"],
)
def test_what_the_deployment_honours_validates(tmp_path: Path, edit: tuple[str, str]) -> None:
    edits = [edit]
    if "_Plant" in edit[1]:
        edits.append(('connector="remote"', 'connector="inprocess"'))
    result = run_main(["validate", str(_ventilation(tmp_path, *edits))])
    assert result.code == 0 and ": 0 errors, 0 warnings" in result.out, result.out


@pytest.mark.parametrize("file_form", port_models.FILE_FORMS)
@pytest.mark.parametrize("port_form", port_models.PORT_FORMS)
def test_a_joined_port_of_no_component_is_refused(
    tmp_path: Path, file_form: str, port_form: str
) -> None:
    spec = port_models.Spec(file_form, port_form, unowned_port=True)
    model = tmp_path / f"ventilation{spec.suffix}"
    model.write_bytes(port_models.document(spec))
    shutil.copy(PROFILE, tmp_path / PROFILE.name)
    result = run_main(["validate", str(model)])
    no_crash(result)
    assert result.code == 1 and codes_in(result.out) == {"A511", "A517"}, result.out
    (line,) = [ln for ln in result.out.splitlines() if ": A517 " in ln]
    assert re.match(rf"{re.escape(str(model))}:\d+:1: error: A517 ", line), line
    assert (
        "port connection 'FanLink' joins port 'PanelPort', which belongs to no component: a "
        "connection joins ports of components; relate the port to the <<CtxComponent>> that owns "
        "it (Papyrus: make it a uml:Port of the component)"
    ) in line
    assert re.search(r" \[(Ventilation::)?FanLink \([^)]+\)\]$", line), line  # the connection


@pytest.mark.parametrize("file_form", port_models.FILE_FORMS)
@pytest.mark.parametrize("port_form", port_models.PORT_FORMS)
def test_a_port_named_like_an_attribute_of_its_component_is_refused(
    tmp_path: Path, file_form: str, port_form: str
) -> None:
    spec = port_models.Spec(file_form, port_form, property_named_like_port=True)
    model = tmp_path / f"ventilation{spec.suffix}"
    model.write_bytes(port_models.document(spec))
    shutil.copy(PROFILE, tmp_path / PROFILE.name)
    result = run_main(["validate", str(model)])
    assert result.code == 1 and codes_in(result.out) == {"N603"}, result.out
    assert (
        ": error: N603 Panel has a port and an attribute both named 'PanelPort' (the generated "
        "Java class would have two fields of that name); rename one ["
    ) in result.out


def test_the_codes_page_shows_this_output(tmp_path: Path, monkeypatch) -> None:
    """docs/diagnostics.md's A516 example is what validate prints for the sample made in-process."""
    page = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    section = page.split("{#a516}", 1)[1].split("\n### ", 1)[0]
    (shown,) = re.findall(r"^ventilation\.uml:.*$", section, flags=re.M)
    model = _ventilation(tmp_path, ('connector="remote"', 'connector="inprocess"'))
    monkeypatch.chdir(tmp_path)
    assert shown in run_main(["validate", model.name]).out.splitlines()
