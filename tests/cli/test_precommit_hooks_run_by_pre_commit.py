"""The hooks of ``.pre-commit-hooks.yaml`` run by real pre-commit in a scratch git repository: pre-commit
reads the file, makes the hook's environment, installs acordcs into it from this repository with pip,
and runs each hook on the staged models, a good one, a bad one and one named like an option.

Offline: pip is told to use no index (``PIP_NO_INDEX``), and finds acordcs's dependencies already
installed, in the test's own environment (on ``PYTHONPATH``); acordcs is built without build
isolation, with the test environment's setuptools (a dev dependency for that reason). pre-commit
itself (a dev dependency) takes the repository from its path. ``pre-commit try-repo`` runs
``acordcs-validate`` as a project would with the hook's own args; ``acordcs-build-check`` needs the
project's args, which only a configuration gives: it runs from a ``.pre-commit-config.yaml``
naming a copy of this repository, its working tree committed (what try-repo does)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

from tests.support.toolchain import ROOT, WEBLAB, entry_point, replace

pytestmark = pytest.mark.slow

PRE_COMMIT = [sys.executable, "-m", "pre_commit"]


def _git(cwd: Path, *args: str) -> str:
    done = subprocess.run(
        ["git", "-c", "user.name=test", "-c", "user.email=test@example.org", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        check=True,
    )
    return done.stdout


@pytest.fixture(scope="module")
def offline_env(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """The environment pre-commit runs in: its own cache (the hooks' environments, kept for the
    module's tests), no package index, this environment's packages visible to pip and the hooks."""
    paths = sysconfig.get_paths()
    site = os.pathsep.join(dict.fromkeys([paths["purelib"], paths["platlib"]]))
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PIP_", "PRE_COMMIT"))}
    env.update(
        PRE_COMMIT_HOME=str(tmp_path_factory.mktemp("pre-commit-home")),
        PIP_NO_INDEX="1",
        # pip reads this variable backwards: "0" turns build isolation off
        PIP_NO_BUILD_ISOLATION="0",
        PYTHONPATH=site,
        GIT_CONFIG_NOSYSTEM="1",
    )
    return env


@pytest.fixture
def project(tmp_path: Path) -> Path:
    """A user's project, a git repository: a good model, one named like an option, a bad one (the
    misspelt rule variable of the documented example); nothing staged yet."""
    repo = tmp_path / "project"
    (repo / "models").mkdir(parents=True)
    _git(repo, "init", "-q")
    shutil.copyfile(WEBLAB, repo / "models" / "app.xmi")
    shutil.copyfile(WEBLAB, repo / "-h.xmi")
    broken = replace(
        WEBLAB.read_text(encoding="utf-8"),
        "smallNarrow: if cycleRate is small",
        "smallNarrow: if cycleRat is small",
        count=2,
    )
    (repo / "models" / "bad.xmi").write_text(broken, encoding="utf-8")
    return repo


def _pre_commit(cwd: Path, env: dict[str, str], *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*PRE_COMMIT, *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=600
    )


def test_validate_hook_passes_good_models_and_fails_a_bad_one(project: Path, offline_env):
    _git(project, "add", "--", "models/app.xmi", "-h.xmi")
    done = _pre_commit(project, offline_env, "try-repo", str(ROOT), "acordcs-validate")
    said = done.stdout + done.stderr
    assert done.returncode == 0, said
    assert "acordcs-gen validate" in said and "Passed" in said

    _git(project, "add", "--", "models/bad.xmi")
    done = _pre_commit(project, offline_env, "try-repo", str(ROOT), "acordcs-validate", "-v")
    said = done.stdout + done.stderr
    assert done.returncode == 1, said
    assert "- hook id: acordcs-validate" in said and "- exit code: 1" in said
    assert "-h.xmi: 0 errors" in said and "models/app.xmi: 0 errors" in said
    assert "models/bad.xmi:" in said and ": error: L402 " in said and "'cycleRat'" in said


def _snapshot_of_this_repository(where: Path) -> tuple[Path, str]:
    """A clone of this repository with its working tree's changes to tracked files committed, and
    that commit (as ``pre-commit try-repo`` makes one)."""
    clone = where / "acordcs"
    _git(where, "clone", "-q", "--no-hardlinks", str(ROOT), str(clone))
    diff = subprocess.run(
        ["git", "diff", "HEAD", "--binary"], cwd=ROOT, capture_output=True, check=True
    ).stdout
    if diff:
        subprocess.run(["git", "apply", "--index"], cwd=clone, input=diff, check=True)
        _git(clone, "commit", "-q", "-m", "the working tree")
    return clone, _git(clone, "rev-parse", "HEAD").strip()


def test_build_check_hook_fails_until_the_output_is_built(project: Path, offline_env, tmp_path):
    repository, rev = _snapshot_of_this_repository(tmp_path)
    (project / ".pre-commit-config.yaml").write_text(
        "repos:\n"
        f"  - repo: {repository}\n"
        f"    rev: {rev}\n"
        "    hooks:\n"
        "      - id: acordcs-build-check\n"
        "        args: [models/app.xmi, --output, gen]\n",
        encoding="utf-8",
    )
    _git(project, "add", "--", ".pre-commit-config.yaml", "models/app.xmi")
    done = _pre_commit(project, offline_env, "run")
    said = done.stdout + done.stderr
    assert done.returncode == 1, said
    assert "acordcs-gen build --check" in said and "Failed" in said
    assert "gen: not up to date: 59 files to write, 0 to delete" in said

    built = subprocess.run(
        [*entry_point(), "build", "models/app.xmi", "-o", "gen", "-q"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert built.returncode == 0, built.stdout + built.stderr
    done = _pre_commit(project, offline_env, "run")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Passed" in done.stdout
