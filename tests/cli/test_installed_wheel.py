"""The wheel, not the editable install: it builds with the declared build requirement, installs in
a fresh virtual environment (no system site-packages) on this interpreter's Python and on the
newest Python of the machine, carries py.typed and the licence, pulls no WebLab package, and its
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


def _pythons() -> list[str]:
    """This interpreter, and the newest Python 3.11+ found on the machine if it is newer."""
    found = {shutil.which(f"python3.{minor}") for minor in range(11, 20)}
    found |= set(glob.glob(os.path.expanduser("~/.pyenv/versions/3.*/bin/python3")))
    versions = {p: _version(p) for p in found if p}
    usable = {p: v for p, v in versions.items() if v and v >= (3, 11)}
    ours = sys.version_info[:2]
    newest = max(usable, key=lambda p: usable[p], default=None)
    pythons = [sys.executable]
    if newest is not None and usable[newest] > ours:
        pythons.append(newest)
    return pythons


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    # Built from a copy: an in-tree build would leave build/ and *.egg-info in the checkout.
    work = tmp_path_factory.mktemp("wheel")
    source = work / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE", "LICENSES/MPL-2.0.txt"):
        (source / name).parent.mkdir(parents=True, exist_ok=True)
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


@pytest.mark.parametrize(
    "python", _pythons(), ids=lambda p: "python" + ".".join(map(str, _version(p) or ()))
)
def test_the_installed_wheel_runs(wheel: Path, python: str, tmp_path: Path) -> None:
    venv = tmp_path / "venv"
    subprocess.run([python, "-m", "venv", str(venv)], check=True, timeout=120, env=CLEAN_ENV)
    pip = [str(venv / "bin" / "python"), "-m", "pip"]
    done = subprocess.run(
        [*pip, "install", "-q", str(wheel)],
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
    licenses = site / f"acordcs-{__version__}.dist-info" / "licenses"
    assert (licenses / "LICENSE").is_file()
    assert (licenses / "LICENSES" / "MPL-2.0.txt").is_file()  # the generated rule parser's
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
