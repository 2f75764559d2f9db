"""docs/update.md's transcript is what ``acordcs-gen update`` prints: the page's commands run against
the WebLab started by its scripts on loopback (as ``make live`` starts it), with the page's model
changes, print the page's lines (standard output, then standard error) and exit as shown. What
differs from run to run is compared by its shape: the ports, the milliseconds an apply took, and
the descriptors' digests (the same digest where the page shows the same one). The page's edits of
the user's code (its ``$ sed -i`` lines) are made where it shows them, between its commands."""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
from pathlib import Path

from acordcs.cli import main
from tests.docs.test_site import _transcripts
from tests.generator.test_shell_scripts_parse_quote_and_run import free_ports
from tests.support import weblab_models as models
from tests.support.toolchain import ROOT, WEBLAB, run_main

PAGE = ROOT / "docs" / "update.md"
NARROW = "smallNarrow: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is slow"


def shape(lines: list[str]) -> list[str]:
    digests: dict[str, str] = {}

    def digest(found: re.Match[str]) -> str:
        return digests.setdefault(found[0], f"<digest {len(digests) + 1}>")

    out = []
    for line in lines:
        line = re.sub(r"127\.0\.0\.1:\d+", "127.0.0.1:<port>", line)
        line = re.sub(r"in \d+\.\d ms", "in <n> ms", line)
        out.append(re.sub(r"(?<![0-9a-f])[0-9a-f]{12}(?![0-9a-f])", digest, line))
    return out


def steps(page: Path) -> list[tuple[str, str]]:
    """The page's ``$ sed -i`` and ``$ acordcs-gen`` lines, in the page's order: (kind, line)."""
    found = []
    for block in re.findall(r"^```\n(.*?)^```", page.read_text(encoding="utf-8"), re.M | re.S):
        for line in block.splitlines():
            if line.startswith("$ sed -i "):
                found.append(("edit", line[2:]))
            elif line.startswith("$ acordcs-gen "):
                found.append(("run", line[2:]))
    return found


def test_the_pages_transcript_is_real(tmp_path: Path, monkeypatch):
    app = tmp_path / "samples" / "weblab" / "app"
    for part in ("components", "monitors"):  # the WebLab's code, as in the repository
        shutil.copytree(WEBLAB.parent / "app" / "weblab_app" / part, app / "weblab_app" / part,
                        ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
    assert main(["build", "-q", str(WEBLAB), "-o", str(app)]) == 0
    (tmp_path / "edited").mkdir()
    (tmp_path / "moved").mkdir()
    models.write_weblab(
        tmp_path / "edited" / "weblab.xmi", models.rule(NARROW, NARROW.replace("slow", "fast"))
    )
    models.write_weblab(tmp_path / "moved" / "weblab.xmi", models.vision_moved)
    run = app / "run"
    run.mkdir(mode=0o700)
    user, lab = free_ports(2)
    env = {
        **{k: v for k, v in os.environ.items() if not k.startswith("ACORDCS_")},
        "PYTHONPATH": os.pathsep.join([str(WEBLAB.parent), str(ROOT / "src")]),
        # what the page exports (live.sh's settings), and free ports
        "ACORDCS_RUN_DIR": str(run),
        "ACORDCS_CLOCK": "real",
        "ACORDCS_UserSide_HOST": "127.0.0.1",
        "ACORDCS_WebLabSide_HOST": "127.0.0.1",
        "ACORDCS_UserSide_PORT": str(user),
        "ACORDCS_WebLabSide_PORT": str(lab),
        "ACORDCS_STOP_TIMEOUT": "5",
    }
    started = subprocess.run(["sh", str(app / "bin" / "start-all")], env=env, capture_output=True,
                             text=True, timeout=120, check=False)  # fmt: skip
    try:
        assert started.returncode == 0, started.stdout + started.stderr
        monkeypatch.chdir(tmp_path)
        for key in [k for k in os.environ if k.startswith("ACORDCS_")]:
            monkeypatch.delenv(key)
        for key, value in env.items():
            monkeypatch.setenv(key, value)
        transcripts = _transcripts(PAGE)
        assert len(transcripts) >= 5, "the page shows the update's transcript"
        order = steps(PAGE)
        assert [line for kind, line in order if kind == "run"] == [t[0] for t in transcripts]
        assert any(kind == "edit" for kind, _ in order), "the page edits the user's code"
        edits = iter(order)
        for command, expected, code in transcripts:
            for kind, line in edits:  # the page's edits before this command
                if kind == "run":
                    break
                subprocess.run(["sh", "-c", line], cwd=tmp_path, check=True, timeout=30)
            done = run_main(shlex.split(command)[1:])
            shown = shape((done.out + done.err).splitlines())
            assert shown == shape(expected), command
            assert done.code == (code if code is not None else 0), command
    finally:
        subprocess.run(["sh", str(app / "bin" / "stop-all")], env=env, capture_output=True,
                       timeout=60, check=False)  # fmt: skip
