"""docs/testing.md's transcripts are what ``acordcs-gen test`` prints: each ``$ acordcs-gen test``
block is run where the page says (the repository, or a folder holding the files its ``$ cat``
lines show, the WebLab with its paper rule mutated, the greenhouse) and its output compared."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from tests.support.toolchain import ROOT, SAMPLES, WEBLAB, run_main

PAGE = (ROOT / "docs" / "testing.md").read_text(encoding="utf-8")
BLOCKS = re.findall(r"```\n(\$ .*?)```", PAGE, flags=re.S)
RULE = "smallNarrow: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is "


def transcripts() -> list[tuple[dict[str, str], str, str]]:
    """(files the block's $ cat lines show, the command's arguments, what it prints)."""
    found = []
    for block in BLOCKS:
        files: dict[str, str] = {}
        for part in re.split(r"^\$ ", block, flags=re.M)[1:]:
            command, _, output = part.partition("\n")
            if command.startswith("cat "):
                files[command[4:]] = output
            elif command.startswith("acordcs-gen test ") and "--trace" not in command:
                found.append((files, command.split()[1:], output))
    return found


@pytest.mark.parametrize(("files", "args", "shown"), transcripts(), ids=lambda x: str(x)[:40])
def test_the_transcript_is_what_the_command_prints(
    files: dict[str, str],
    args: list[str],
    shown: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
):
    model = args[1]
    if model.startswith("samples/") and not files:
        monkeypatch.chdir(ROOT)
    else:
        monkeypatch.chdir(tmp_path)
        for name, text in files.items():
            (tmp_path / name).write_text(text, encoding="utf-8")
        if model == "weblab.xmi":  # the page's copy, with the paper rule concluding fast
            text = WEBLAB.read_text(encoding="utf-8").replace(RULE + "slow", RULE + "fast")
            Path(model).write_text(text, encoding="utf-8")
            shutil.copy(WEBLAB.with_name("weblab.scenarios.yaml"), "weblab.scenarios.yaml")
        else:
            target = Path(model)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(SAMPLES / "tutorial" / "greenhouse.uml", target)
    result = run_main(args)
    assert result.out + result.err == shown


def test_the_page_shows_a_failing_and_a_refused_scenario():
    outputs = "".join(shown for _, _, shown in transcripts())
    assert "FAIL " in outputs and "error: S810" in outputs and "error: S804" in outputs


def test_the_trace_shown_is_what_the_command_writes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    block = next(b for b in BLOCKS if "--trace" in b)
    command, head, *_ = re.split(r"^\$ ", block, flags=re.M)[1:]
    assert command.startswith("acordcs-gen test samples/weblab/weblab.xmi --trace trace")
    name, _, shown = head.partition("\n")
    csv_file = name.split()[-1]
    import acordcs.scenarios.trace_files as trace_files

    # the CSV is compared here; the plots are drawn (and looked at) in tests/scenarios
    monkeypatch.setattr(trace_files, "_plot", lambda *args: [])
    monkeypatch.chdir(ROOT)
    result = run_main(["test", "samples/weblab/weblab.xmi", "--trace", str(tmp_path / "trace")])
    assert result.code == 0
    written = (tmp_path / csv_file).read_text(encoding="utf-8").splitlines()[:4]
    assert written == shown.splitlines()
