"""The pre-commit hooks of ``.pre-commit-hooks.yaml`` work as pre-commit runs them: each hook's
``entry``, then its ``args`` (the user's ``args`` replace the hook's), then the staged files that
match ``files`` when ``pass_filenames`` is true, in the project's root; run here with the installed
``acordcs-gen`` and this tree's sources first on ``PYTHONPATH``.

PyYAML is not a dependency: the file is read with the small reader below, which knows only the
subset the file uses (a list of flat mappings; plain, single-quoted and boolean scalars; flow lists)
and refuses anything else, so the file cannot drift into syntax it would misread."""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.support.toolchain import ROOT, WEBLAB, entry_point, replace

HOOKS_FILE = ROOT / ".pre-commit-hooks.yaml"


# ----------------------------------------------------------------- a reader for the file's YAML
def _scalar(text: str) -> str | bool | list[str]:
    text = text.strip()
    if text.startswith("[") and text.endswith("]"):
        items = [item.strip() for item in text[1:-1].split(",")]
        return [_plain(item) for item in items if item]
    if text in ("true", "false"):
        return text == "true"
    return _plain(text)


def _plain(text: str) -> str:
    if text.startswith("'"):
        assert text.endswith("'") and len(text) > 1, f"unterminated quoted scalar {text!r}"
        return text[1:-1].replace("''", "'")
    assert re.fullmatch(r"[^'\"\[\]{}&*!|>%@`#,][^\"\[\]{}#]*", text), f"unsupported {text!r}"
    assert not re.match(r"[-?:](\s|$)", text), f"an indicator in YAML: {text!r}"
    assert ": " not in text and not text.endswith(":"), f"a mapping in YAML: {text!r}"
    # what YAML (PyYAML: 1.1) reads as a number, null or boolean
    not_string = r"[-+.\d_:eE]+|null|Null|NULL|~|(?i:y|n|yes|no|on|off|true|false)"
    assert not re.fullmatch(not_string, text), f"not a string in YAML: {text!r}"
    return text


def read_hooks(text: str) -> list[dict[str, str | bool | list[str]]]:
    hooks: list[dict[str, str | bool | list[str]]] = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        match = re.fullmatch(r"(- |  )([a-z_]+): (.+)", line)
        assert match, f"line {number}: not in the subset the reader knows: {line!r}"
        start, key, value = match.groups()
        if start == "- ":
            hooks.append({})
        assert hooks, f"line {number}: a key outside any hook"
        assert key not in hooks[-1], f"line {number}: {key} given twice"
        hooks[-1][key] = _scalar(value)
    return hooks


HOOKS = {hook["id"]: hook for hook in read_hooks(HOOKS_FILE.read_text(encoding="utf-8"))}


def test_the_reader_reads_its_subset_and_refuses_the_rest():
    text = "# c\n- id: a\n  files: '\\.(x|y)$'\n  args: [m.xmi, --output, gen]\n  p: false\n"
    assert read_hooks(text) == [
        {"id": "a", "files": "\\.(x|y)$", "args": ["m.xmi", "--output", "gen"], "p": False}
    ]
    for bad in (
        "- id: a\n  args:\n    - x\n",
        '- id: "a"\n',
        "- id: a # c\n",
        "- id: a\n id: b\n",
        "- id: a\n  name: b: c\n",
        "- id: a\n  rev: 0.1\n",
        "- id: a\n  v: yes\n",
        "- id: a\n  v: - x\n",
    ):
        with pytest.raises(AssertionError):
            read_hooks(bad)
    try:  # where PyYAML happens to be installed, it reads the file the same
        import yaml
    except ImportError:
        return
    assert list(HOOKS.values()) == yaml.safe_load(HOOKS_FILE.read_text(encoding="utf-8"))


def test_the_file_declares_the_two_hooks_as_pre_commit_expects():
    assert list(HOOKS) == ["acordcs-validate", "acordcs-build-check", "acordcs-test"]
    for hook in HOOKS.values():
        assert {"id", "name", "entry", "language"} <= hook.keys()
        assert hook["language"] == "python"  # installs this repository, which provides acordcs-gen
        assert shlex.split(hook["entry"])[0] == "acordcs-gen"
        files = re.compile(hook["files"])
        assert files.search("models/app.xmi") and files.search("model.uml")
        assert not files.search("app.xmi.bak") and not files.search("gen/app.py")
    assert HOOKS["acordcs-validate"]["pass_filenames"] is True
    # a test reads exactly one model too, and runs when its scenario files change
    assert HOOKS["acordcs-test"]["pass_filenames"] is False
    assert re.search(HOOKS["acordcs-test"]["files"], "models/app.scenarios.yaml")
    # a build reads exactly one model: given in args, never the staged file names
    assert HOOKS["acordcs-build-check"]["pass_filenames"] is False


# -------------------------------------------------------------------- running them as pre-commit
def run_hook(
    hook_id: str, cwd: Path, staged: list[str], args: list[str] | None = None
) -> subprocess.CompletedProcess[str]:
    """The hook run as pre-commit runs it, in ``cwd`` (the project's root) with ``staged`` files."""
    hook = HOOKS[hook_id]
    files = [name for name in staged if re.search(hook["files"], name)]
    assert files, "pre-commit runs a hook only when a staged file matches its files"
    command = shlex.split(hook["entry"])
    command = [*entry_point(), *command[1:], *(hook.get("args", []) if args is None else args)]
    if hook.get("pass_filenames", True):
        command += files
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), env.get("PYTHONPATH")]))
    return subprocess.run(
        command, cwd=cwd, env=env, capture_output=True, text=True, timeout=120, check=False
    )


def _broken(text: str) -> str:
    """The misspelt variable of the documented example, in both places BOUML writes the rule."""
    return replace(
        text, "smallNarrow: if cycleRate is small", "smallNarrow: if cycleRat is small", count=2
    )


@pytest.fixture
def project(tmp_path: Path) -> Path:
    """A user's project: its model ``models/app.xmi`` (the WebLab sample), no generated files."""
    (tmp_path / "models").mkdir()
    shutil.copyfile(WEBLAB, tmp_path / "models" / "app.xmi")
    return tmp_path


def test_validate_hook_passes_the_sample():
    done = run_hook("acordcs-validate", ROOT, ["samples/weblab/weblab.xmi", "README.md"])
    assert done.returncode == 0, done.stdout + done.stderr
    assert "samples/weblab/weblab.xmi: 0 errors" in done.stdout
    assert "README.md" not in done.stdout  # not a model: not passed


def test_validate_hook_reads_a_model_named_like_an_option(project: Path):
    # pre-commit passes a root-level file as it is named: '-h.xmi' must not be read as -h
    shutil.copyfile(WEBLAB, project / "-h.xmi")
    done = run_hook("acordcs-validate", project, ["-h.xmi", "models/app.xmi"])
    assert done.returncode == 0, done.stdout + done.stderr
    assert "-h.xmi: 0 errors" in done.stdout and "models/app.xmi: 0 errors" in done.stdout
    assert HOOKS["acordcs-validate"]["args"][-1] == "--"  # what makes it so: your args end so


def test_validate_hook_fails_a_misspelt_rule_variable(project: Path):
    model = project / "models" / "app.xmi"
    broken = _broken(model.read_text(encoding="utf-8"))
    (project / "models" / "broken.xmi").write_text(broken, encoding="utf-8")
    # the line of the taggedValue holding the rule (the first of the two places BOUML writes)
    line = broken[: broken.index("smallNarrow: if cycleRat")].count("\n") + 1
    done = run_hook("acordcs-validate", project, ["models/app.xmi", "models/broken.xmi"])
    assert done.returncode == 1, done.stdout + done.stderr
    assert "models/app.xmi: 0 errors" in done.stdout
    assert f"models/broken.xmi:{line}:1: error: L402 " in done.stdout
    assert "variable 'cycleRat'" in done.stdout


def test_build_check_hook_fails_until_the_output_is_built(project: Path):
    args = ["models/app.xmi", "--output", "gen"]
    done = run_hook("acordcs-build-check", project, ["models/app.xmi"], args)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "gen: not up to date: 59 files to write, 0 to delete" in done.stderr
    assert not (project / "gen").exists()  # --check writes nothing

    built = subprocess.run(
        [*entry_point(), "build", "models/app.xmi", "-o", "gen"],
        cwd=project,
        env={**os.environ, "PYTHONPATH": str(ROOT / "src")},
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert built.returncode == 0, built.stdout + built.stderr
    done = run_hook("acordcs-build-check", project, ["models/app.xmi"], args)
    assert done.returncode == 0, done.stdout + done.stderr

    # an edited generated file is found out
    descriptor = project / "gen" / "WebLab.descriptor.xml"
    descriptor.write_text(descriptor.read_text(encoding="utf-8") + "\n", encoding="utf-8")
    done = run_hook("acordcs-build-check", project, ["models/app.xmi"], args)
    assert done.returncode == 1, done.stdout + done.stderr


def test_build_check_hook_without_args_is_a_usage_error(project: Path):
    done = run_hook("acordcs-build-check", project, ["models/app.xmi"])
    assert done.returncode == 2
    assert "Missing argument 'MODEL'" in done.stderr


# ------------------------------------------------------------------- the documentation
def _section() -> str:
    build_doc = (ROOT / "docs" / "build.md").read_text(encoding="utf-8")
    return build_doc.split("## Checking models in CI\n", 1)[1].split("\n## ", 1)[0]


def test_readme_check_transcript_is_what_the_command_prints(tmp_path: Path):
    block = _section().split("```\n$ ", 1)[1].split("```", 1)[0]
    command, *shown = block.splitlines()
    assert command == "acordcs-gen build samples/weblab/weblab.xmi -o gen --check"
    (tmp_path / "samples" / "weblab").mkdir(parents=True)
    shutil.copyfile(WEBLAB, tmp_path / "samples" / "weblab" / "weblab.xmi")
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    done = subprocess.run(
        [*entry_point(), *shlex.split(command)[1:]],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert [*(done.stdout + done.stderr).splitlines(), "$ echo $?", str(done.returncode)] == shown


def test_readme_pre_commit_config_names_the_hooks():
    ids = re.findall(r"^\s+- id: (\S+)$", _section(), flags=re.M)
    assert ids and set(ids) <= set(HOOKS)
    assert set(HOOKS) <= set(ids)


def test_test_hook_runs_the_scenarios_of_the_model_given():
    model = WEBLAB.relative_to(ROOT).as_posix()
    done = run_hook("acordcs-test", ROOT, ["samples/weblab/weblab.scenarios.yaml"], [model])
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.splitlines()[-1].startswith("7 scenarios: 7 passed, 0 failed")
