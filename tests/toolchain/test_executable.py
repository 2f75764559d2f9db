"""The ``acordcs-gen`` executable's start and end (acordcs.cli.launch): the model files are
parsed ahead on a thread, and the process leaves with os._exit once its output is flushed."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

from acordcs.xmi import source as xmlsafe
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


def _wait(path: str) -> None:
    slot = xmlsafe._prefetched[path]
    assert slot.done.wait(30)


def test_a_prefetched_parse_is_used_once(tmp_path: Path) -> None:
    path = str(tmp_path / "m.xmi")
    Path(path).write_bytes(WEBLAB.read_bytes())
    xmlsafe.prefetch([path])
    _wait(path)
    prefetched = xmlsafe._prefetched[path].result
    first = xmlsafe.read_xml(path)
    assert first is prefetched and first.root is not None
    second = xmlsafe.read_xml(path)  # not prefetched any more: parsed again
    assert second is not first and second.root is not None


def test_a_file_changed_after_the_prefetch_is_read_again(tmp_path: Path) -> None:
    path = str(tmp_path / "m.xmi")
    Path(path).write_bytes(WEBLAB.read_bytes())
    xmlsafe.prefetch([path])
    _wait(path)
    time.sleep(0.01)
    Path(path).write_text("<broken", encoding="utf-8")
    reading = xmlsafe.read_xml(path)
    assert reading.root is None and reading.diagnostics[0].code == "X104"


def test_a_prefetch_of_a_file_that_vanished_reports_it_as_usual(tmp_path: Path) -> None:
    path = str(tmp_path / "m.xmi")
    Path(path).write_bytes(WEBLAB.read_bytes())
    xmlsafe.prefetch([path])
    _wait(path)
    os.remove(path)
    reading = xmlsafe.read_xml(path)
    assert reading.root is None and reading.diagnostics[0].code == "X101"
