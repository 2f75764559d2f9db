"""``acordcs-gen update`` finds the running containers as the application's scripts do (bin/env.sh,
with the same environment) and says what it could not do: exit 2 for a directory that is no
built application, settings its scripts refuse, no container answering, or a token the
containers refuse; exit 1 for a model with errors (nothing built, nothing changed); ``--dry-run``
prints the plan and changes neither the directory nor the running container; the command's own
update applies and a second one finds nothing to do. On the SmartRoom, one container started by
its script."""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.generator.test_shell_scripts_parse_quote_and_run import free_ports
from tests.support.generator import build, snapshot
from tests.support.toolchain import (
    ROOT,
    SMARTROOM,
    CliResult,
    replace,
    update_under,
)

LIGHT = "vacant: if occupancy is empty then Lights.dimmer is off"
DIMMED = "vacant: if occupancy is empty then Lights.dimmer is low"


def environment(run: Path, port: int, **more: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("ACORDCS_")}
    return {
        **env,
        "PYTHONPATH": str(ROOT / "src"),
        "ACORDCS_RUN_DIR": str(run),
        "ACORDCS_CLOCK": "real",
        "ACORDCS_Room_HOST": "127.0.0.1",
        "ACORDCS_Room_PORT": str(port),
        "ACORDCS_STOP_TIMEOUT": "5",
        **more,
    }


def update(env: dict[str, str], *args: str) -> CliResult:
    return update_under(env, *args)


@pytest.fixture(scope="module")
def room(tmp_path_factory) -> Iterator[tuple[Path, dict[str, str]]]:
    """The SmartRoom built and started by its script (its container serving on loopback)."""
    root = tmp_path_factory.mktemp("room")
    app, run = root / "app", root / "run"
    run.mkdir(mode=0o700)
    model = root / "smartroom.xmi"
    shutil.copy(SMARTROOM, model)
    assert build(model, app).code == 0
    env = environment(run, free_ports(1)[0])
    started = subprocess.run(["sh", str(app / "bin" / "start-all")], env=env,
                             capture_output=True, text=True, timeout=120, check=False)  # fmt: skip
    try:
        assert started.returncode == 0, started.stdout + started.stderr
        yield root, env
    finally:
        subprocess.run(["sh", str(app / "bin" / "stop-all")], env=env, capture_output=True,
                       timeout=60, check=False)  # fmt: skip


def edited(root: Path, name: str, old: str, new: str) -> Path:
    folder = root / name
    folder.mkdir(exist_ok=True)
    path = folder / "smartroom.xmi"
    path.write_text(replace(SMARTROOM.read_text(encoding="utf-8"), old, new, 2), encoding="utf-8")
    return path


def test_a_directory_that_is_no_started_application_is_exit_2(tmp_path: Path):
    env = environment(tmp_path / "run", free_ports(1)[0])
    missing = update(env, str(SMARTROOM), "-o", str(tmp_path / "nowhere"))
    assert missing.code == 2 and "is not a directory" in missing.err
    empty = update(env, str(SMARTROOM), "-o", str(tmp_path))
    assert empty.code == 2 and "has no bin/env.sh: not an application built by" in empty.err
    app = tmp_path / "app"
    assert build(SMARTROOM, app).code == 0
    (tmp_path / "run").mkdir(mode=0o700)
    files = snapshot(app)
    for args in ((), ("--dry-run",)):
        idle = update(env, str(SMARTROOM), "-o", str(app), *args)
        assert idle.code == 2, idle.both
        assert "Room: not running (nothing answers" in idle.err
        assert "acordcs-gen update: no container of " in idle.err
        assert "start it (bin/start-all) with the same environment" in idle.err
    assert snapshot(app) == files


def test_settings_the_scripts_refuse_are_exit_2(room, tmp_path: Path):
    root, env = room
    done = update({**env, "ACORDCS_CLOCK": "sometimes"}, str(SMARTROOM), "-o", str(root / "app"))
    assert done.code == 2
    assert (
        "env.sh refused its settings: acordcs-gen update: ACORDCS_CLOCK is 'sometimes'" in done.err
    )


def test_another_token_is_refused_exit_2(room):
    root, env = room
    done = update({**env, "ACORDCS_TOKEN": "not-the-one"}, str(SMARTROOM), "-o", str(root / "app"))
    assert done.code == 2
    assert (
        "Room: it refused the token (ACORDCS_TOKEN, or the token file of the run directory)"
        in done.err
    )


def test_a_model_with_errors_is_exit_1_and_changes_nothing(room):
    root, env = room
    app = root / "app"
    files = snapshot(app)
    broken = edited(root, "broken", LIGHT, LIGHT.replace("Lights.dimmer", "Lights.dimer"))
    done = update(env, str(broken), "-o", str(app))
    assert done.code == 1, done.both
    assert (
        "acordcs-gen update: " in done.err and "the model has errors; nothing was built" in done.err
    )
    assert snapshot(app) == files


def test_dry_run_then_update_then_nothing_to_do(room):
    root, env = room
    app = root / "app"
    files = snapshot(app)
    dimmed = edited(root, "dimmed", LIGHT, DIMMED)
    line = "~ policy set Lighting: rule vacant: ... is off -> ... is low"
    dry = update(env, str(dimmed), "-o", str(app), "--dry-run")
    assert dry.code == 0, dry.both
    # the SmartRoom's classes as built have no code: said first, as the container said at start
    lines = dry.out.splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("running: "))
    assert all(": warning: " in line and " has no code, and " in line for line in lines[:first])
    assert lines[first].startswith("running: Room (127.0.0.1:")
    assert f"plan: 1 change\n{line}\ndry run: nothing changed\n" in dry.out
    assert snapshot(app) == files
    done = update(env, str(dimmed), "-o", str(app))
    assert done.code == 0, done.both
    assert "Room: applied 1 change in " in done.out
    assert "built: 3 written, 0 deleted" in done.out  # the descriptors and the rules file
    again = update(env, str(dimmed), "-o", str(app))
    assert (
        again.code == 0 and "plan: 0 changes (the running application is the model's)" in again.out
    )
    assert "Room: runs descriptor " in again.out and "already: nothing to do" in again.out
    status = subprocess.run(["sh", str(app / "bin" / "Room-status")], env=env,
                            capture_output=True, text=True, check=False)  # fmt: skip
    digest = again.out.split("Room: runs descriptor ", 1)[1][:12]
    assert status.returncode == 0 and ", descriptor sha256 " + digest in status.stdout
