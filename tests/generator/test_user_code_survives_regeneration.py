"""Generation gap in the ``python`` target: the user's component and monitor classes (``components/*.py``, ``monitors/*.py``)
are written once and never overwritten; the manifest records them as the user's. When their
component leaves the model (renamed here), the file stays with every line the user wrote, is
reported by the build (renamed, its id the same: G704 says which new file to move the code into;
then as orphaned), and is no longer imported by the registry; the generated files are rewritten
as usual."""

from __future__ import annotations

import json
from pathlib import Path

from tests.support.generator import build, imported, snapshot, weblab_variant
from tests.support.toolchain import WEBLAB

USER_CODE = """

    def move(self, speed, turn):  # the user's code
        self.turns = getattr(self, "turns", 0) + 1
        return min(speed, self.get("maxSpeed"))
"""


def test_user_files_survive_edits_rebuilds_and_renames(tmp_path: Path):
    out = tmp_path / "out"
    assert build(WEBLAB, out).code == 0
    components = out / "weblab_app" / "components"
    locomotion, vision = components / "Locomotion.py", components / "Vision.py"
    manifest = json.loads((out / ".acordcs-manifest.json").read_text(encoding="utf-8"))
    assert manifest["files"]["weblab_app/components/Vision.py"]["user"] is True
    assert "user" not in manifest["files"]["weblab_app/base/Vision.py"]

    # the user implements two components
    locomotion.write_text(locomotion.read_text(encoding="utf-8") + USER_CODE, encoding="utf-8")
    vision.write_text(
        "# my vision code\nfrom weblab_app.base.Vision import VisionBase\n\n\n"
        "class Vision(VisionBase):\n    def detect(self):\n        return 42\n",
        encoding="utf-8",
    )
    edited = {p: d for p, (d, _) in snapshot(components).items()}

    # a rebuild of the same model, then a forced one, then --check: the user's files untouched
    result = build(WEBLAB, out)
    assert result.code == 0 and "up to date" in result.out, result.both
    result = build(WEBLAB, out, "--force")
    assert result.code == 0 and "nothing changed" in result.out, result.both
    assert build(WEBLAB, out, "--check").code == 0
    assert {p: d for p, (d, _) in snapshot(components).items()} == edited

    # the user's class is the one the registry maps and the container runs
    with imported(out, "weblab_app") as package:
        assert package.FACTORIES["Locomotion"].move.__code__.co_filename == str(locomotion)
        with package.assemble_application() as app:
            lab = app.container("WebLabSide")
            assert lab.find("Locomotion").instance.move(300.0, 5.0) == 200.0

    # the component Vision is renamed Eye in the model
    renamed = weblab_variant(tmp_path, ('name="Vision" ', 'name="Eye" '))
    result = build(renamed, out)
    assert result.code == 0, result.both
    assert f"wrote {out}/weblab_app/base/Eye.py" in result.out
    assert f"wrote {out}/weblab_app/components/Eye.py" in result.out
    assert f"deleted {out}/weblab_app/base/Vision.py" in result.out
    for verb in ("wrote", "deleted"):  # neither written nor deleted
        assert f"{verb} {out}/weblab_app/components/Vision.py" not in result.out
    # the same id, renamed: G704 says where the code is and what to move
    assert (
        f"{out}/weblab_app/components/Vision.py:1:1: warning: G704 weblab_app/components/"
        "Vision.py is your code for component Vision, which the model now names Eye"
    ) in result.out
    after = {p: d for p, (d, _) in snapshot(components).items()}
    assert {p: after[p] for p in edited} == edited  # every line the user wrote, kept
    for line in USER_CODE.splitlines():
        assert line in locomotion.read_text(encoding="utf-8")
    registry = (out / "weblab_app" / "registry.py").read_text(encoding="utf-8")
    assert "components.Vision" not in registry and "components.Eye import Eye" in registry
    with imported(out, "weblab_app") as package:
        assert set(package.FACTORIES) >= {"Eye", "Locomotion"} and "Vision" not in package.FACTORIES
        with package.assemble_application() as app:
            assert app.container("WebLabSide").find("Eye").instance.type_name == "Eye"

    # still kept and reported by the next builds; the name coming back adopts the user's file
    manifest = json.loads((out / ".acordcs-manifest.json").read_text(encoding="utf-8"))
    assert manifest["files"]["weblab_app/components/Vision.py"]["user"] is True
    result = build(renamed, out, "--force")
    assert (
        f"acordcs-gen: {out}/weblab_app/components/Vision.py is your code for "
        "WebLab::ContextAwareNavigation::Components::Vision, no longer in the model: kept, "
        "no longer used by the generated code"
    ) in result.err
    result = build(WEBLAB, out)
    assert result.code == 0, result.both
    assert "components/Vision.py is your code for" not in result.err
    assert {p: d for p, (d, _) in snapshot(components).items()}["Vision.py"] == edited["Vision.py"]
    assert (components / "Eye.py").is_file()  # now the orphan, of a component renamed back
    assert "G704 weblab_app/components/Eye.py is your code for component Eye" in result.out


def test_a_deleted_user_file_is_written_again(tmp_path: Path):
    assert build(WEBLAB, tmp_path).code == 0
    user = tmp_path / "weblab_app" / "components" / "Access.py"
    original = user.read_bytes()
    user.unlink()
    result = build(WEBLAB, tmp_path)
    assert result.code == 0, result.both
    assert result.out.splitlines()[0] == f"wrote {user}"
    assert user.read_bytes() == original


def test_a_file_where_a_user_file_goes_is_adopted_not_overwritten(tmp_path: Path):
    mine = tmp_path / "weblab_app" / "components" / "Access.py"
    mine.parent.mkdir(parents=True)
    mine.write_text("# written before the first build\n", encoding="utf-8")
    result = build(WEBLAB, tmp_path)
    assert result.code == 0, result.both
    assert mine.read_text(encoding="utf-8") == "# written before the first build\n"


def test_user_monitor_code_runs_survives_and_is_reported_when_its_monitor_goes(tmp_path: Path):
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-t", "python").code == 0
    telemetry = out / "weblab_app" / "monitors" / "Telemetry.py"
    telemetry.write_text(
        "# my telemetry monitor\nfrom weblab_app.base.Telemetry import TelemetryBase\n\n\n"
        "class Telemetry(TelemetryBase):\n"
        "    def on_document(self, note):\n"
        "        return {'batteryVoltage': float(note.document.getroot().get('volts'))}\n",
        encoding="utf-8",
    )
    mine = telemetry.read_text(encoding="utf-8")
    # the user's class is the monitor the container runs, and its hook reads the documents
    with imported(out, "weblab_app") as package, package.assemble_application() as app:
        lab = app.container("WebLabSide")
        assert type(lab.monitor("Telemetry")).__module__ == "weblab_app.monitors.Telemetry"
        lab.publish_context("Locomotion", '<telemetry volts="11.8"/>')
        assert lab.monitor("Telemetry").attributes["batteryVoltage"] == 11.8
    # the monitor is renamed in the model: the user's file stays, is reported, is not imported
    renamed = weblab_variant(
        tmp_path,
        ('name="Telemetry" ', 'name="Odometry" '),
        ("Telemetry.progress", "Odometry.progress", 4),
    )
    result = build(renamed, out, "-t", "python")
    assert result.code == 0, result.both
    assert f"deleted {out}/weblab_app/base/Telemetry.py" in result.out
    assert (
        f"acordcs-gen: {out}/weblab_app/monitors/Telemetry.py is your code for "
        "WebLab::ContextAwareNavigation::Adaptation::Telemetry, no longer in the model: kept"
    ) in result.err
    assert telemetry.read_text(encoding="utf-8") == mine
    registry = (out / "weblab_app" / "registry.py").read_text(encoding="utf-8")
    assert "monitors.Telemetry " not in registry and "monitors.Odometry import Odometry" in registry
