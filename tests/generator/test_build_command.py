"""``acordcs-gen build`` as a command: exit codes 0/1/2, no traceback, the installed executable
(which leaves with os._exit) writes complete files, the output option is required, a progress bar
only on a terminal, and nothing is ever written through a symbolic link."""

from __future__ import annotations

import contextlib
import io
import os
from pathlib import Path

from acordcs.cli import main
from tests.support.generator import build, snapshot
from tests.support.toolchain import WEBLAB, no_crash, run_main, run_process


def test_installed_executable_writes_complete_files(tmp_path: Path):
    result = run_process(["build", str(WEBLAB), "-o", str(tmp_path)])
    no_crash(result)
    assert result.code == 0, result.both
    in_process = tmp_path / "in-process"
    assert build(WEBLAB, in_process).code == 0
    made = {p: d for p, (d, _) in snapshot(tmp_path).items() if not p.startswith("in-process/")}
    assert made == {p: d for p, (d, _) in snapshot(in_process).items()}
    again = run_process(["build", str(WEBLAB), "-o", str(tmp_path)])
    assert again.code == 0 and "up to date" in again.out


def test_output_is_required(tmp_path: Path):
    result = run_main(["build", str(WEBLAB)])
    assert result.code == 2
    assert "Missing option '-o' / '--output'" in result.err


def test_output_that_is_a_file_is_a_usage_error(tmp_path: Path):
    (tmp_path / "file").write_text("x", encoding="utf-8")
    result = build(WEBLAB, tmp_path / "file")
    no_crash(result)
    assert result.code == 2 and "is a file" in result.err


def test_no_write_through_symbolic_links(tmp_path: Path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    (out / "rules").symlink_to(elsewhere, target_is_directory=True)
    result = build(WEBLAB, out)
    no_crash(result)
    assert result.code == 2
    assert (
        "rules is a symbolic link; generated files are never written or deleted through links"
        in result.err
    )
    assert list(elsewhere.iterdir()) == [] and sorted(p.name for p in out.iterdir()) == ["rules"]


def test_progress_bar_only_on_a_terminal(tmp_path: Path):
    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    err = Terminal()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = main(["build", str(WEBLAB), "-o", str(tmp_path / "a")])
    assert code == 0
    assert "building: target rules" in err.getvalue()
    result = build(WEBLAB, tmp_path / "b")
    assert "building" not in result.err


def test_warnings_of_the_model_are_shown_and_the_build_goes_on(tmp_path: Path):
    from tests.support.generator import weblab_variant

    anchor = '<ACORDCS:CtxPolicy xmi:id="BOUML_STELT_0x20302_4"'
    model = weblab_variant(tmp_path, (anchor, anchor.replace("xmi:id", 'colour="red" xmi:id')))
    result = build(model, tmp_path / "out")
    assert result.code == 0
    text = model.read_text(encoding="utf-8")
    line = text[: text.index('colour="red"')].count("\n") + 1
    assert result.out.startswith(
        f"{model}:{line}:1: warning: T303 <<CtxPolicy>> has no tag 'colour'"
    )
    assert os.path.isfile(tmp_path / "out" / "WebLab.descriptor.xml")
