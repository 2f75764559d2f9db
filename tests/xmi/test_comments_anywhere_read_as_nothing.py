"""XML comments and processing instructions may stand anywhere in an export (a modeller's note, a
tool's marker): every reader passes over them. Each sample and tool model, with a comment and a
processing instruction before every element, reads to the same findings as without them."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from tests.support.toolchain import ROOT, SAMPLES, run_main

MODELS = [
    SAMPLES / "weblab" / "weblab.xmi",
    SAMPLES / "smartroom" / "smartroom.xmi",
    SAMPLES / "papyrus" / "thermostat.uml",
    *sorted((ROOT / "tests" / "xmi" / "tool_models").glob("*.xmi")),
]


def commented(text: str) -> str:
    """``text`` with ``<!-- note --><?tool mark?>`` before every element inside the root."""
    root = re.search(r"<(?![?!])[^>]*>", text)  # the root's start tag (after prolog comments)
    assert root is not None
    head, body = text[: root.end()], text[root.end() :]
    return head + re.sub(r"<(?![/?!])", "<!-- note --><?tool mark?><", body)


@pytest.mark.parametrize("model", MODELS, ids=lambda p: p.name)
def test_comments_and_instructions_change_nothing(model: Path, tmp_path: Path):
    plain = tmp_path / "plain" / model.name
    noted = tmp_path / "noted" / model.name
    for path, text in ((plain, model.read_text(encoding="utf-8")),):
        path.parent.mkdir()
        path.write_text(text, encoding="utf-8")
    noted.parent.mkdir()
    noted.write_text(commented(model.read_text(encoding="utf-8")), encoding="utf-8")
    assert noted.read_text(encoding="utf-8").count("<!-- note -->") > 10
    for folder in (plain.parent, noted.parent):  # a Papyrus model's profile beside it
        profile = model.with_name("ACORDCS.profile.uml")
        if profile.is_file():
            shutil.copy(profile, folder)
    expected = run_main(["validate", "--format", "json", str(plain)])
    got = run_main(["validate", "--format", "json", str(noted)])
    assert "internal error" not in got.err, got.err
    assert got.code == expected.code

    def findings(out: str) -> list[tuple[str, str]]:
        return sorted(re.findall(r'"code": "(\w+)".*?"message": "(.*?)"', out, flags=re.S))

    assert findings(got.out) == findings(expected.out)
