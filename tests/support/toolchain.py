"""Helpers of the generator tests: paths, running the CLI, editing copies of the samples."""

from __future__ import annotations

import contextlib
import io
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples"
WEBLAB = SAMPLES / "weblab" / "weblab.xmi"
SMARTROOM = SAMPLES / "smartroom" / "smartroom.xmi"
# Real third-party exports: read in place, never copied into the project.
XMI_SAMPLES = (ROOT / ".." / "shared" / "reference" / "xmi-samples").resolve()


@dataclass
class CliResult:
    code: int
    out: str
    err: str

    @property
    def both(self) -> str:
        return self.out + self.err


def run_main(args: list[str]) -> CliResult:
    """``acordcs.cli.main(args)`` in-process, with stdout and stderr captured.

    Any exception escaping ``main`` propagates: the tests want to see it.
    """
    from acordcs.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return CliResult(code, out.getvalue(), err.getvalue())


def entry_point() -> list[str]:
    """The installed ``acordcs-gen`` of the interpreter running the tests."""
    script = Path(sys.executable).parent / "acordcs-gen"
    if script.exists():
        return [str(script)]
    return [sys.executable, "-m", "acordcs.cli"]


def run_process(args: list[str], cwd: Path | None = None) -> CliResult:
    proc = subprocess.run(
        [*entry_point(), *args],
        capture_output=True,
        text=True,
        cwd=cwd or ROOT,
        timeout=120,
        check=False,
    )
    return CliResult(proc.returncode, proc.stdout, proc.stderr)


def no_crash(result: CliResult) -> None:
    """No Python traceback and no 'internal error' catch-all anywhere in the output."""
    assert "Traceback" not in result.both, result.both
    assert "internal error" not in result.both, result.both
    assert "Z901" not in result.both, result.both


# ----------------------------------------------------------------------------- editing samples
def replace(text: str, old: str, new: str, count: int = 1) -> str:
    """``text`` with ``old`` replaced by ``new``; ``old`` must occur exactly ``count`` times."""
    found = text.count(old)
    assert found == count, f"expected {count} occurrence(s) of {old!r}, found {found}"
    return text.replace(old, new)


def element_span(text: str, name: str) -> tuple[int, int]:
    """Start and end offsets of the ``packagedElement`` (a class) named ``name``, up to its own
    closing tag (the sample's classes nest no packagedElement)."""
    match = re.search(rf'<packagedElement xmi:type="uml:\w+" name="{re.escape(name)}"', text)
    assert match, f"no class {name!r}"
    end = text.index("</packagedElement>", match.start()) + len("</packagedElement>")
    return match.start(), end


def replace_in_element(text: str, name: str, old: str, new: str, count: int = 1) -> str:
    start, end = element_span(text, name)
    return text[:start] + replace(text[start:end], old, new, count) + text[end:]


def remove_regex(text: str, pattern: str) -> str:
    """``text`` without the one match of ``pattern`` (DOTALL)."""
    matches = list(re.finditer(pattern, text, re.DOTALL))
    assert len(matches) == 1, f"{len(matches)} matches of {pattern!r}"
    return text[: matches[0].start()] + text[matches[0].end() :]
