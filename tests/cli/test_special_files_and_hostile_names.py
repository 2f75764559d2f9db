"""Input that is not a regular file, and file names that carry line breaks (issue 14): a named pipe
or a device is refused at once with exit 2 (it would block or never end); a newline in a name is
escaped in every line of text output, so it cannot forge a diagnostic or summary line."""

from __future__ import annotations

import os
import shutil
import threading
from pathlib import Path

import pytest

from tests.support.toolchain import WEBLAB, CliResult, no_crash, run_main

FORGED = "x.xmi: error X999: forged"


def _main_with_deadline(args: list[str], unblock: Path | None = None) -> CliResult:
    """run_main on a thread; a call still running after 20 s fails the test (a hang)."""
    done: list[CliResult] = []
    thread = threading.Thread(target=lambda: done.append(run_main(args)), daemon=True)
    thread.start()
    thread.join(20)
    in_time = bool(done)
    if not in_time and unblock is not None:  # let the stuck thread go: give the pipe a writer
        fd = os.open(unblock, os.O_WRONLY | os.O_NONBLOCK)
        os.close(fd)
        thread.join(5)
    assert in_time, f"acordcs-gen {' '.join(args)} did not return within 20 s"
    return done[0]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
@pytest.mark.parametrize("command", ["validate", "inspect", "build"])
def test_a_named_pipe_is_refused_with_exit_2(command: str, tmp_path: Path) -> None:
    fifo = tmp_path / "model.xmi"
    os.mkfifo(fifo)
    extra = ["-o", str(tmp_path / "out")] if command == "build" else []
    result = _main_with_deadline([command, str(fifo), *extra], unblock=fifo)
    no_crash(result)
    assert result.code == 2
    assert "X101" in result.both and "a named pipe, not a regular file" in result.both


def test_a_device_is_refused_with_exit_2() -> None:
    result = _main_with_deadline(["validate", "/dev/zero"])
    assert result.code == 2 and "a character device, not a regular file" in result.out


@pytest.fixture
def forged_name(tmp_path: Path) -> Path:
    path = tmp_path / f"a\n{FORGED}.xmi"
    shutil.copyfile(WEBLAB, path)
    return path


def _no_forged_line(text: str) -> None:
    for line in text.splitlines():
        assert not line.startswith(FORGED), text
    assert "\\u000a" in text, text


def test_validate_escapes_a_newline_in_the_file_name(forged_name: Path) -> None:
    result = run_main(["validate", str(forged_name)])
    assert result.code == 0
    _no_forged_line(result.out)
    missing = run_main(["validate", f"{forged_name}\nmissing"])
    assert missing.code == 2
    _no_forged_line(missing.out)


def test_inspect_escapes_a_newline_in_the_file_name(forged_name: Path) -> None:
    result = run_main(["inspect", str(forged_name)])
    assert result.code == 0
    _no_forged_line(result.out)


def test_build_escapes_newlines_in_the_model_and_output_names(
    forged_name: Path, tmp_path: Path
) -> None:
    out = tmp_path / f"out\n{FORGED}"
    result = run_main(["build", str(forged_name), "-o", str(out), "--target", "rules"])
    assert result.code == 0, result.both
    _no_forged_line(result.both)
    failed = run_main(["build", f"{forged_name}\nmissing", "-o", str(out)])
    assert failed.code == 2
    _no_forged_line(failed.both)
