"""``acordcs-gen build`` compiles the classes of the components tagged ``language=java`` when a
JDK is present (``java-classes/<digest>/``, the digest of the sources under ``java/``), and a
container's start loads those without a JDK; a build that finds the same sources compiles
nothing; a class that does not compile is the build's error at javac's ``file:line`` (exit 1,
the files in place, the earlier classes kept); without a JDK the build says so in a note.

The oracle for "compiled for Java 17": the class file's own header (magic ``CAFEBABE``, major
version 61), as the JVM specification lays it out. Needs a JDK (``make test`` installs one):
outside CI the module skips without it; with ``CI=true`` it fails.
"""

from __future__ import annotations

import json
import os
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.generator import build
from tests.support.toolchain import SAMPLES

MODEL = SAMPLES / "mixed" / "greenhouse.uml"


@pytest.fixture(scope="module")
def out(tmp_path_factory: pytest.TempPathFactory) -> Path:
    if shutil.which("javac") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("no javac on PATH; CI=true, so it must be installed (make test does)")
        pytest.skip("no javac on PATH (openjdk-17-jdk-headless)")
    out = tmp_path_factory.mktemp("built") / "app"
    shutil.copytree(MODEL.parent / "app", out)
    built = build(MODEL, out)
    assert built.code == 0, built.both
    return out


def classes(out: Path) -> list[Path]:
    return sorted(p for p in (out / "java-classes").iterdir() if (p / ".complete").is_file())


def test_the_build_compiles_the_java_components_for_java_17(out: Path):
    (made,) = classes(out)
    header = (made / "mixedgreenhouse" / "Vent.class").read_bytes()[:8]
    magic, _minor, major = struct.unpack(">IHH", header)
    assert (magic, major) == (0xCAFEBABE, 61)
    # what Vent uses came along (its base, the Java API); the Python-tagged components did not
    assert (made / "mixedgreenhouse" / "VentBase.class").is_file()
    assert (made / "org" / "acordcs" / "runtime" / "Port$Link.class").is_file()
    assert not (made / "mixedgreenhouse" / "Panel.class").exists()
    stamp = (made / ".complete").stat().st_mtime_ns
    again = build(MODEL, out)
    assert again.code == 0 and "up to date" in again.out and "compiled" not in again.out
    assert classes(out) == [made] and (made / ".complete").stat().st_mtime_ns == stamp


def test_a_start_without_a_jdk_loads_the_classes_the_build_compiled(out: Path, tmp_path):
    bare = tmp_path / "bin"  # no javac on PATH, an empty cache: only the build's classes serve
    bare.mkdir()
    env = {**os.environ, "PYTHONPATH": str(out), "PATH": str(bare), "XDG_CACHE_HOME": str(tmp_path)}
    done = subprocess.run(
        [sys.executable, "-m", "mixedgreenhouse_app.House", "--duration", "1"],
        cwd=out, env=env, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert "faults: 0" in done.stdout
    assert not list(tmp_path.rglob("*.class"))  # nothing compiled at start


def test_a_class_that_does_not_compile_fails_the_build_at_its_line(out: Path, tmp_path):
    broken = tmp_path / "app"
    shutil.copytree(out, broken)
    before = classes(broken)
    source = broken / "java" / "mixedgreenhouse" / "Vent.java"
    lines = source.read_text(encoding="utf-8").splitlines()
    at = next(i for i, line in enumerate(lines) if "return reference -" in line)
    lines[at] = lines[at].replace(";", "")
    source.write_text("\n".join(lines) + "\n", encoding="utf-8")
    manifest = (broken / ".acordcs-manifest.json").read_bytes()
    done = build(MODEL, broken)
    assert done.code == 1, done.both
    assert (
        f"{source}:{at + 1}: error: component Vent (tagged language=java): its Java class does "
        "not compile: ';' expected" in done.err
    )
    assert "Traceback" not in done.both
    # the output intact: the same files, the earlier classes kept, none made for these sources
    assert (broken / ".acordcs-manifest.json").read_bytes() == manifest
    assert all((broken / rel).is_file() for rel in json.loads(manifest)["files"])
    assert classes(broken) == [broken / "java-classes" / p.name for p in before]
    assert not [p for p in (broken / "java-classes").iterdir() if p.name.startswith(".")]


def test_without_a_jdk_the_build_says_the_start_compiles(out: Path, tmp_path, monkeypatch):
    copy = tmp_path / "app"
    shutil.copytree(out, copy, ignore=shutil.ignore_patterns("java-classes"))
    monkeypatch.setenv("PATH", str(tmp_path))  # no javac
    done = build(MODEL, copy)
    assert done.code == 0, done.both
    assert (
        "acordcs-gen: no javac on PATH: the Java classes of component Vent (tagged "
        "language=java) are not compiled by the build; each container hosting them compiles "
        "them at start" in done.err
    )
    assert not (copy / "java-classes").exists()


def test_a_renamed_or_removed_operation_is_drift_at_the_java_method(out: Path, tmp_path):
    copy = tmp_path / "app"
    shutil.copytree(out, copy)
    shutil.copy(MODEL.parent / "ACORDCS.profile.uml", tmp_path)
    text = MODEL.read_text(encoding="utf-8")
    renamed = text.replace('xmi:id="_Vent.calibrate" name="calibrate"',
                           'xmi:id="_Vent.calibrate" name="adjust"')  # fmt: skip
    start = renamed.index('<ownedOperation xmi:type="uml:Operation" xmi:id="_Vent.lastNotice"')
    end = renamed.index("</ownedOperation>", start) + len("</ownedOperation>")
    model = tmp_path / "greenhouse.uml"
    model.write_text(renamed[:start] + renamed[end:], encoding="utf-8")
    done = build(model, copy)
    user = copy / "java" / "mixedgreenhouse" / "Vent.java"
    lines = user.read_text(encoding="utf-8").splitlines()
    at = {name: 1 + next(i for i, line in enumerate(lines) if f" {name}(" in line)
          for name in ("calibrate", "lastNotice")}  # fmt: skip
    assert (
        f"{user}:{at['calibrate']}:1: warning: G704 method calibrate() of Java class Vent "
        "implements operation calibrate, which the model now names adjust (id _Vent.calibrate): "
        "rename the method to adjust" in done.out
    )
    assert (
        f"{user}:{at['lastNotice']}:1: warning: G704 method lastNotice() of Java class Vent "
        "implements operation lastNotice (id _Vent.lastNotice), which is no longer in the model"
        in done.out
    )
    assert "[Vent (_Vent.calibrate)]" in done.out
    # and javac, run by the build, refuses the class in its own words: exit 1
    assert done.code == 1 and "does not override abstract method adjust(double)" in done.err
