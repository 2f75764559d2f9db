"""The tuning table has one source (weblab_experiment/tuning.toml): the README's rendering is the
current one, and its values are the code's and the model's (each row checked against the
constants it states)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest
from weblab_experiment import grid, summary, tuning
from weblab_sim import camera, course, experiment, floor, network, world

from tests.support.toolchain import ROOT

from .conftest import SAMPLE_DIR


def samples_script():
    spec = importlib.util.spec_from_file_location(
        "build_samples", ROOT / "samples" / "build_samples.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_readme_renders_the_current_table() -> None:
    readme = (SAMPLE_DIR / "README.md").read_text(encoding="utf-8")
    assert tuning.readme_block(readme) == tuning.markdown(), (
        "run: cd samples/weblab && python -m weblab_experiment.tuning --write"
    )


def test_the_check_option_says_whether_the_readme_is_current() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "weblab_experiment.tuning", "--check"],
        cwd=SAMPLE_DIR,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr


def ms(seconds: float) -> str:
    return f"{seconds * 1000:g}"


def path_value(name: str) -> str:
    path = floor.make_path(name)
    turns = ", ".join(f"{t:+.0f}" for t in path.turns())
    return f"{len(path.points) - 1} segments, {path.length / 1000:.1f} m, turns of {turns} degrees"


def expected() -> dict[str, list[str]]:
    """Per row, the figures its value must state, computed from the code and the model."""
    p = network.PROFILES
    res, cam, lan = p["residential"], p["campus"], p["LAN"]
    model = samples_script()
    speeds = [experiment.CONDITIONS[c].forward_speed for c in ("fixed_50", "fixed_150")]
    return {
        "latency": [
            f"{ms(res.latency)}, {ms(cam.latency)}, {ms(lan.latency)} ms",
            f"jitter {ms(res.jitter)}, {ms(cam.jitter)}, {ms(lan.jitter)} ms",
        ],
        "grab_time": [f"{res.grab_time:g} s"],
        "cpu_time": [f"{res.cpu_time:g} s"],
        "panorama_frame": [f"{camera.PANORAMA_FRAME_BYTES / 1000:g} KB"],
        "speed_terms": [
            term.strip().replace(":= ", "")
            for terms in (model.CYCLE_RATE, model.MAX_SPEED)
            for term in terms.split(";")
        ],
        "fps_terms": [term.strip().replace(":= ", "") for term in model.FPS.split(";")],
        "residential_bandwidth": [f"{res.bandwidth / 1e6:g} Mbit/s"],
        "other_links": [
            f"{cam.bandwidth / 1e6:g} Mbit/s, {lan.bandwidth / 1e6:g} Mbit/s",
            f"{network.BUFFER_BYTES / 1000:g} KB",
        ],
        "default_path": [path_value("default")],
        "sharp_path": [path_value("sharp")],
        "fixed_speeds": [f"{speeds[0]:g} and {speeds[1]:g} mm/s"],
        "time_cap": [f"{experiment.TIME_CAP:g} s"],
        "sweep": [", ".join(f"{v:g}" for v in grid.SWEEP) + " mm/s"],
        "person": [f"after {experiment.PATIENCE} control cycles", f"{world.HUMAN_DELAY:g} s"],
        "person_repeats": [
            f"after {experiment.REPEATS} recoveries",
            f"less than {experiment.SAME_PLACE_MM:g} mm",
        ],
        "course": [
            f"{course.SIDE_BIAS_DEG:g} degrees",
            f"more than {course.BACKWARDS_DEG:g} degrees",
            f"more than {course.CARRIED_DEG:g} degrees",
        ],
        "recovered": ["100 mm or more"],
        "course_beyond": [f"more than {course.BEYOND_MM:g} mm ahead"],
        "course_against": [
            f"more than {course.BACKWARDS_DEG:g} degrees",
            f"more than {course.AGAINST_DEG:g} degrees",
            f"within {course.AGAINST_DEG:g} degrees",
        ],
        "family_paths": [path_value("right"), path_value("gentle")]
        + [
            "segments " + ", ".join(f"{length:g}" for length, _ in floor.PATHS[name]) + " mm"
            for name in ("right", "gentle")
        ],
        "lab_guard": [
            f"more than {world.STOP_MM:g} mm",
            f"more than {world.AHEAD_MM:g} mm past",
            f"more than {course.BACKWARDS_DEG:g} degrees",
            f"more than {experiment.BACKWARDS_MM:g} mm has followed",
        ],
        "unlimited": [
            f"{experiment.CONDITIONS[f'no_speed_policy_{v}'].forward_speed:g}" for v in (50, 150)
        ],
        "sharp_scope": [", ".join(paths) for paths in summary.SCOPES.values()],
    }


@pytest.mark.parametrize("key", sorted(expected()))
def test_a_row_states_the_values_the_code_uses(key: str) -> None:
    rows = {r.key: r for r in tuning.rows()}
    for figure in expected()[key]:
        assert figure in rows[key].value, (key, figure, rows[key].value)


def test_the_recovered_row_is_the_models_rule() -> None:
    rules = (ROOT / "samples" / "build_samples.py").read_text(encoding="utf-8")
    assert "Telemetry.progress > Recovery.lostAt + 100" in rules


def test_every_row_says_where_its_value_came_from() -> None:
    rows = tuning.rows()
    assert {r.basis for r in rows} == set(tuning.BASES)
    assert len({r.key for r in rows}) == len(rows)
    assert all(r.parameter and r.value and r.why for r in rows)
