"""The wheel, not the editable install: it builds with the declared build requirement, installs in
a fresh virtual environment (no system site-packages) on every Python version its classifiers
name (``Programming Language :: Python :: 3.x`` in pyproject.toml: what it claims is what is
tested), carries py.typed, the rule grammar and the MIT licence, pulls no WebLab package, and its
``acordcs-gen`` runs: version, a clean sample, a refused diagram file, the profile and a model
exported."""

from __future__ import annotations

import glob
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from acordcs import __version__
from tests.support.toolchain import ROOT

pytestmark = [pytest.mark.slow, pytest.mark.service]
# A fresh environment sees nothing of this one: with PYTHONPATH naming a checkout, pip would take
# its acordcs for installed and the commands would run the checkout, not the wheel.
CLEAN_ENV = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
SAMPLES = [
    ROOT / "samples" / "weblab" / "weblab.xmi",
    ROOT / "samples" / "papyrus" / "thermostat.uml",
]


def _unavailable(what: str, detail: str) -> None:
    """Skip outside CI (the package index or a Python is missing here); fail in CI."""
    reason = f"{what}: {detail[-1500:]}"
    if os.environ.get("CI") == "true":
        pytest.fail(f"{reason}; CI=true, so it must work", pytrace=False)
    pytest.skip(reason)


def _version(python: str) -> tuple[int, ...] | None:
    try:
        done = subprocess.run(
            [python, "-c", "import sys; print(*sys.version_info[:2])"],
            capture_output=True,
            text=True,
            timeout=30,
            check=True,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return tuple(int(x) for x in done.stdout.split())


def _classified() -> list[tuple[int, int]]:
    """The Python versions pyproject.toml's classifiers name."""
    text = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    found = re.findall(r'"Programming Language :: Python :: 3\.(\d+)"', text)
    return sorted((3, int(minor)) for minor in found)


def _interpreter(version: tuple[int, int]) -> str | None:
    """An interpreter of ``version`` on the machine (this one first), or None."""
    if sys.version_info[:2] == version:
        return sys.executable
    found = {shutil.which("python{}.{}".format(*version))}
    found |= set(
        glob.glob(os.path.expanduser("~/.pyenv/versions/{}.{}.*/bin/python3".format(*version)))
    )
    return next((p for p in sorted(filter(None, found)) if _version(p) == version), None)


def test_the_classifiers_name_the_python_the_project_requires():
    assert _classified()[0] == (3, 11)  # requires-python = ">=3.11"
    assert sys.version_info[:2] in _classified()


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    # Built from a copy: an in-tree build would leave build/ and *.egg-info in the checkout.
    work = tmp_path_factory.mktemp("wheel")
    source = work / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy2(ROOT / name, source / name)
    shutil.copytree(
        ROOT / "src", source / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info")
    )
    done = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(work), str(source)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    if done.returncode != 0:
        _unavailable(
            "pip wheel failed (it needs setuptools>=77 from the package index)", done.stderr
        )
    (built,) = work.glob("acordcs-*.whl")
    return built


@pytest.mark.parametrize("version", _classified(), ids=lambda v: "python{}.{}".format(*v))
def test_the_installed_wheel_runs(wheel: Path, version: tuple[int, int], tmp_path: Path) -> None:
    python = _interpreter(version)
    if python is None:
        _unavailable("no interpreter of Python {}.{} on this machine".format(*version), "")
    venv = tmp_path / "venv"
    # A fresh environment without a pip of its own: this process's pip installs into it
    # (``--python``), which spares each version the seconds ensurepip takes; and the files are
    # not byte-compiled at install (``--no-compile``, most of the install's time): the commands
    # below compile what they import, as they would run it.
    subprocess.run(
        [python, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=120, env=CLEAN_ENV
    )
    pip = [sys.executable, "-m", "pip", "--python", str(venv / "bin" / "python")]
    done = subprocess.run(
        [*pip, "install", "-q", "--no-compile", str(wheel)],
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    if done.returncode != 0:
        _unavailable("installing the wheel's dependencies failed", done.stderr)
    listed = subprocess.run(
        [*pip, "list"], capture_output=True, text=True, check=True, env=CLEAN_ENV
    ).stdout
    names = {line.split()[0].lower() for line in listed.splitlines()[2:] if line.strip()}
    assert "acordcs" in names
    assert not names & {"pymunk", "opencv-python-headless", "matplotlib", "jinja2"}, names
    site = next((venv / "lib").glob("python3.*/site-packages"))
    assert (site / "acordcs" / "py.typed").is_file()
    info = site / f"acordcs-{__version__}.dist-info"
    assert [p.name for p in (info / "licenses").iterdir()] == ["LICENSE"]
    metadata = (info / "METADATA").read_text(encoding="utf-8")
    assert "\nLicense-Expression: MIT\n" in metadata and "\nLicense-File: LICENSE\n" in metadata
    assert (site / "acordcs" / "rules" / "rules.lark").is_file()  # lark's parser is built from it
    assert (site / "acordcs" / "profile" / "ACORDCS.profile.uml").is_file()

    where = subprocess.run(
        [str(venv / "bin" / "python"), "-c", "import acordcs; print(acordcs.__file__)"],
        capture_output=True,
        text=True,
        check=True,
        env=CLEAN_ENV,
    )
    assert where.stdout.startswith(str(site)), where.stdout  # the wheel's, not a checkout's
    gen = str(venv / "bin" / "acordcs-gen")
    version = subprocess.run(
        [gen, "--version"], capture_output=True, text=True, check=True, env=CLEAN_ENV
    )
    assert version.stdout == f"acordcs-gen, version {__version__}\n"
    clean = subprocess.run(
        [gen, "validate", *map(str, SAMPLES)], capture_output=True, text=True, env=CLEAN_ENV
    )
    assert clean.returncode == 0, clean.stdout + clean.stderr
    assert clean.stdout.count(": 0 errors, 0 warnings, 0 infos") == len(SAMPLES)
    notation = tmp_path / "model.notation"
    notation.write_text("<xmi:XMI xmlns:xmi='http://www.omg.org/XMI'/>", encoding="utf-8")
    refused = subprocess.run(
        [gen, "validate", str(notation)], capture_output=True, text=True, env=CLEAN_ENV
    )
    assert refused.returncode == 2 and re.search(r": error: X109 ", refused.stdout)
    exported = subprocess.run(
        [gen, "profile", "export", str(tmp_path / "profiles")],
        capture_output=True,
        text=True,
        env=CLEAN_ENV,
    )
    assert exported.returncode == 0, exported.stderr
    assert sorted(p.name for p in (tmp_path / "profiles").iterdir()) == [
        "ACORDCS.profile.uml",
        "ACORDCS.xmi",
    ]
    instance = subprocess.run(
        [gen, "export", str(SAMPLES[0]), "-o", str(tmp_path / "emf" / "model.xmi")],
        capture_output=True,
        text=True,
        env=CLEAN_ENV,
    )
    assert instance.returncode == 0, instance.stdout + instance.stderr
    assert sorted(p.name for p in (tmp_path / "emf").iterdir()) == ["acordcs.ecore", "model.xmi"]
