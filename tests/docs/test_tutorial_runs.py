"""The tutorial (docs/tutorial.md) is run as a reader would run it: in a fresh folder holding a link
to the repository's ``samples/``, every ``$`` command of its ``console`` blocks, in order, through
``bash`` with the virtual environment's commands first on the PATH, each printing exactly the lines
the page shows under it (standard output and error together, as a terminal shows them), with the
exit status of each ``$ echo $?``; every ``python`` block whose first line is ``# <path>``, and every ``text`` block whose
first line is ``// <path>`` (a model in the text notation), is the file the reader writes there,
before the commands that follow it."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.toolchain import ROOT

PAGE = ROOT / "docs" / "tutorial.md"

# A console block's command and what follows it, up to the next command.
Step = tuple[str, str, list[str]]  # ("run", command, expected lines) or ("file", path, text)


def steps() -> list[tuple[str, str, object]]:
    found: list[tuple[str, str, object]] = []
    text = PAGE.read_text(encoding="utf-8")
    for info, body in re.findall(r"^```(\w*)\n(.*?)^```", text, flags=re.M | re.S):
        if info == "python" and body.startswith("# "):
            path, _, code = body.partition("\n")
            found.append(("file", path[2:].strip(), code))
        elif info == "text" and body.startswith("// "):  # a model in the text notation
            path, _, model = body.partition("\n")
            found.append(("file", path[3:].strip(), model))
        elif info == "console":
            command: str | None = None
            expected: list[str] = []
            for line in body.splitlines():
                if line.startswith("$ "):
                    if command is not None:
                        found.append(("run", command, expected))
                    command, expected = line[2:], []
                else:
                    expected.append(line)
            if command is not None:
                found.append(("run", command, expected))
    return found


def test_the_page_has_the_steps_the_issue_asks_for():
    commands = " ".join(c for kind, c, _ in steps() if kind == "run")
    for needed in ("profile export", "validate", "build", "python -m", "sed -i"):
        assert needed in commands, needed
    assert [p for kind, p, _ in steps() if kind == "file"] == [
        "greenhouse/greenhouse.acord",
        "greenhouse/app/greenhouse_app/components/Sensor.py",
        "greenhouse/app/greenhouse_app/components/Vent.py",
    ]


def test_the_model_the_page_writes_is_the_sample():
    """The page's model is samples/tutorial/greenhouse.acord, the text of greenhouse.uml (the
    samples' own test holds those two equal)."""
    written = next(text for kind, path, text in steps() if path == "greenhouse/greenhouse.acord")
    assert written == (ROOT / "samples" / "tutorial" / "greenhouse.acord").read_text("utf-8")


@pytest.mark.slow
def test_every_command_prints_what_the_page_shows(tmp_path: Path):
    (tmp_path / "samples").symlink_to(ROOT / "samples")
    venv_bin = str(Path(sys.executable).parent)
    env = {
        **{k: v for k, v in os.environ.items() if not k.startswith("PYTHON")},
        "PATH": os.pathsep.join([venv_bin, os.environ.get("PATH", "")]),
        "PYTHONUNBUFFERED": "1",  # lines in the order a terminal shows them
        "COLUMNS": "200",
    }
    status: int | None = None
    for kind, what, expected in steps():
        if kind == "file":
            path = tmp_path / what
            assert path.parent.is_dir(), f"{what}: the build should have made its folder"
            path.write_text(str(expected), encoding="utf-8")
            continue
        if what == "echo $?":
            assert expected == [str(status)], "exit status"
            continue
        done = subprocess.run(
            ["bash", "-c", f"{what} 2>&1"],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=300,
        )
        status = done.returncode
        assert done.stdout.splitlines() == expected, what
