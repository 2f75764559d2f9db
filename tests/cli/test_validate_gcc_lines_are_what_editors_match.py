"""``acordcs-gen validate --format gcc`` prints each finding as gcc does, so that an editor's
problem matcher takes it: every error and warning line is matched by VS Code's ``$gcc`` pattern
(its regular expression, the oracle) at the file, line and column the JSON format gives; info is
gcc's ``note``; no summary line; the exit code is the text format's."""

from __future__ import annotations

import json
import re

from acordcs.cli.report import render
from acordcs.diagnostics import Severity, diagnostic
from acordcs.model.reading import ModelReading
from tests.support.toolchain import SAMPLES, run_main

# VS Code's built-in $gcc problem matcher (vscode/src/vs/workbench/contrib/tasks/common/problemMatcher.ts)
GCC = re.compile(r"^(.*?):(\d+):(\d*):?\s+(?:fatal\s+)?(warning|error):\s+(.*)$")
TYPOS = SAMPLES / "mistakes" / "typos.xmi"


def test_every_finding_is_matched_at_the_place_json_gives():
    gcc = run_main(["validate", "--format", "gcc", str(TYPOS)])
    text = run_main(["validate", str(TYPOS)])
    found = json.loads(run_main(["validate", "--format", "json", str(TYPOS)]).out)
    assert gcc.code == text.code == 1
    lines = gcc.out.splitlines()
    diags = [d for f in found["files"] for d in f["diagnostics"]]
    assert len(lines) == len(diags) > 0
    for line, d in zip(lines, diags, strict=True):
        m = GCC.match(line)
        assert m, line
        place = (m[1], int(m[2]), int(m[3]), m[4])
        assert place == (d["file"], d["line"], d["column"], d["severity"])
        assert m[5].startswith(d["code"] + " ")
    assert not any(ln.endswith(" infos") for ln in lines)  # no summary


def test_info_is_a_note_and_quiet_keeps_what_reaches_the_threshold():
    info = diagnostic("R209", "exporter unknown", file="m.xmi", line=3, column=7)
    error = diagnostic("T305", "tag 'engine' is 'fuzy'", file="m.xmi", line=9, column=1)
    reading = ModelReading("m.xmi", None, None, [info, error])  # type: ignore[arg-type]
    assert render([reading], "gcc") == (
        "m.xmi:3:7: note: R209 exporter unknown\nm.xmi:9:1: error: T305 tag 'engine' is 'fuzy'\n"
    )
    assert render([reading], "gcc", at_least=Severity.WARNING) == (
        "m.xmi:9:1: error: T305 tag 'engine' is 'fuzy'\n"
    )
