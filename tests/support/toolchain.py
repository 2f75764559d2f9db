"""Helpers of the toolchain tests: paths, the real third-party exports, running the CLI, editing
copies of the samples, reading a model built with the BOUML writer."""

from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples"
WEBLAB = SAMPLES / "weblab" / "weblab.xmi"
SMARTROOM = SAMPLES / "smartroom" / "smartroom.xmi"


# ------------------------------------------------------------------ the real third-party exports
def _main_checkout(root: Path) -> Path:
    """The main checkout of the repository holding ``root`` (``root`` itself unless ``root`` is a
    linked git worktree, whose ``.git`` file names a git directory that names the common one)."""
    git = root / ".git"
    try:
        gitdir = root / git.read_text(encoding="utf-8").split("gitdir:", 1)[1].strip()
        common = gitdir / (gitdir / "commondir").read_text(encoding="utf-8").strip()
    except (OSError, IndexError):  # a directory (the main checkout), or no git at all
        return root
    return common.resolve().parent


def _shared() -> Path:
    """``../shared`` beside the repository: ``$ACORDCS_SHARED`` if set, else beside this checkout,
    else beside the main checkout when this one is a linked worktree."""
    if os.environ.get("ACORDCS_SHARED"):
        return Path(os.environ["ACORDCS_SHARED"]).resolve()
    beside = (ROOT / ".." / "shared").resolve()
    if beside.is_dir():
        return beside
    main = (_main_checkout(ROOT) / ".." / "shared").resolve()
    return main if main.is_dir() else beside


# Read in place, never copied into the project.
REFERENCE = _shared() / "reference"
XMI_SAMPLES = REFERENCE / "xmi-samples"
XMI_OTHER_TOOLS = REFERENCE / "xmi-other-tools"
EXPORT_SUFFIXES = (".xmi", ".uml")


def _unavailable(what: Path) -> None:
    """Skip the running test, or fail it when ``CI`` is ``true`` (CI must provide ../shared)."""
    reason = (
        f"../shared/reference/{what.relative_to(REFERENCE)} not found: the real third-party "
        f"exports live outside the repository; looked at {what} (put the shared folder beside the "
        "repository or set ACORDCS_SHARED to it)"
    )
    if os.environ.get("CI") == "true":
        pytest.fail(f"{reason}; CI=true, so it must be there", pytrace=False)
    pytest.skip(reason)


def reference_dir(folder: Path = XMI_SAMPLES) -> Path:
    """``folder`` (under ../shared/reference), if it is there: else skip, or fail with CI=true."""
    if not folder.is_dir():
        _unavailable(folder)
    return folder


def xmi_sample(name: str, folder: Path = XMI_SAMPLES) -> Path:
    """The real export ``name`` in ``folder``: skip, or fail with CI=true, when it is not there."""
    path = reference_dir(folder) / name
    if not path.is_file():
        _unavailable(path)
    return path


def reference_files(folder: Path = XMI_SAMPLES) -> list[Path]:
    """The exports (.xmi, .uml) in ``folder``, sorted: skip, or fail with CI=true, without it."""
    return sorted(p for p in reference_dir(folder).iterdir() if p.suffix in EXPORT_SUFFIXES)


@dataclass(frozen=True)
class MissingReference:
    """Stands for the files of an absent reference folder in a parametrisation made at collection
    time: ``tests/conftest.py`` skips (or, with CI=true, fails) a test given one, before its body."""

    folder: Path

    @property
    def name(self) -> str:  # the test id, as for a file
        return f"{self.folder.name}-missing"

    def refuse(self) -> None:
        _unavailable(self.folder)


def reference_params(folder: Path = XMI_SAMPLES) -> list[Path | MissingReference]:
    """For ``parametrize``: the exports in ``folder``, or one :class:`MissingReference` when the
    folder is absent (listing it at collection time must not crash the collection)."""
    if not folder.is_dir():
        return [MissingReference(folder)]
    return reference_files(folder)


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
def write_model(tmp_path: Path, text: str) -> Path:
    """``text`` written to ``tmp_path/model.xmi``."""
    path = tmp_path / "model.xmi"
    path.write_text(text, encoding="utf-8")
    return path


def codes_in(out: str) -> set[str]:
    """The diagnostic codes in ``validate``'s text output."""
    return set(re.findall(r": (?:error|warning|info): ([A-Z]\d{3}) ", out))


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


# ------------------------------------------------------------------------- models built for a test
def rule_and_tag_findings(tmp_path: Path, build: Callable) -> list[tuple[str, str]]:
    """(code, message) of the rule (L) and tag (T) diagnostics of a model that ``build(writer,
    package)`` fills in, written by the BOUML writer and read back."""
    from acordcs.model.reading import read_model
    from tools.bouml_writer import bouml
    from tools.bouml_writer.elements import Pkg

    gen = bouml
    root = Pkg("Model")
    build(gen, root.package("App"))
    path = tmp_path / "model.xmi"
    path.write_text(gen.BoumlWriter("Model").write(root), encoding="utf-8")
    reading = read_model(str(path))
    return [(d.code, d.message) for d in reading.diagnostics if d.code[0] in "LT"]


@contextlib.contextmanager
def environ(env: dict[str, str]) -> Iterator[None]:
    """This process's environment is ``env`` (only) for the block."""
    saved = dict(os.environ)
    os.environ.clear()
    os.environ.update(env)
    try:
        yield
    finally:
        os.environ.clear()
        os.environ.update(saved)


def update_under(env: dict[str, str], *args: str) -> CliResult:
    """``acordcs-gen update ARGS...`` in this process, under the environment ``env`` (the one the
    application's scripts run with)."""
    with environ(env):
        done = run_main(["update", *args])
    no_crash(done)
    return done
