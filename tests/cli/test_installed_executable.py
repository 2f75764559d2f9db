"""The installed ``acordcs-gen`` executable (acordcs.cli.run): its output reaches a pipe complete
(it leaves with os._exit only once the output is flushed), and file arguments named like option
values or missing are read as files."""

from __future__ import annotations

import json
from pathlib import Path

from tests.support.toolchain import WEBLAB, no_crash, replace, run_process


def _many_problems(tmp_path: Path, copies: int = 40) -> list[Path]:
    text = WEBLAB.read_text(encoding="utf-8")
    text = replace(text, 'frequency="1" base_Element', 'frequency="0" base_Element')
    text = replace(text, 'CtxMonitor:frequency" value="1"/>', 'CtxMonitor:frequency" value="0"/>')
    paths = []
    for n in range(copies):
        path = tmp_path / f"model{n}.xmi"
        path.write_text(text, encoding="utf-8")
        paths.append(path)
    return paths


def test_all_output_reaches_the_pipe_before_the_process_ends(tmp_path: Path) -> None:
    paths = _many_problems(tmp_path)
    result = run_process(["validate", "--format", "json", *map(str, paths)])
    no_crash(result)
    assert result.code == 1
    report = json.loads(result.out)  # complete: os._exit came after the flush
    assert len(report["files"]) == len(paths)
    assert all(any(d["code"] == "T306" for d in f["diagnostics"]) for f in report["files"])


def test_option_values_and_missing_files_are_not_a_problem(tmp_path: Path) -> None:
    (tmp_path / "text").write_text("not a model", encoding="utf-8")  # named like an option value
    result = run_process(["validate", "--format", "text", str(WEBLAB), str(tmp_path / "absent")])
    no_crash(result)
    assert result.code == 2
    assert "absent" in result.out and "X101" in result.out
    assert f"{WEBLAB}: 0 errors, 0 warnings, 0 infos" in result.out
