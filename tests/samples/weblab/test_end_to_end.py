"""Short runs of the generated WebLab application on the simulator: metrics, conditions, faults."""

from __future__ import annotations

import pytest
from weblab_sim import camera, detector, experiment
from weblab_sim.world import Script

METRICS = (
    "cycles_per_s",
    "speed_mm_s",
    "time_s",
    "finished",
    "recoveries",
    "recovery_actions",
    "stripe_losses",
    "user_requests",
    "fps",
    "mm_per_cycle",
    "faults",
    "sim_s",
    "wall_s",
    "sim_per_wall",
)


def test_a_short_run_follows_the_stripe_with_its_metrics(weblab_app: None) -> None:
    m = experiment.run("LAN", 0, "adaptive", time_cap=20.0)
    assert set(METRICS) <= set(m)
    assert all(isinstance(m[k], int | float) for k in METRICS)
    assert m["sim_s"] == pytest.approx(20.0, abs=1.0) and m["finished"] == 0
    # Twenty seconds of control at about 1.7 cycles/s, on the stripe: well along it, no help.
    assert m["cycles"] >= 25 and m["progress_mm"] > 1500.0
    assert m["user_requests"] == 0 and m["faults"] == 0
    assert m["mm_per_cycle"] == pytest.approx(m["speed_mm_s"] / m["cycles_per_s"])


def test_runs_repeat_for_a_seed_and_differ_between_seeds(weblab_app: None) -> None:
    def trajectory(seed: int) -> list:
        return experiment.run("campus", seed, time_cap=8.0, series=True)["series"]["trajectory"]

    assert trajectory(5) == trajectory(5)
    assert trajectory(5) != trajectory(6)


def test_fixed_conditions_switch_the_policies_off(weblab_app: None) -> None:
    m = experiment.run("residential", 0, "fixed_50", time_cap=10.0, series=True)
    assert {v for _, v in m["series"]["max_speed"]} == {200.0}  # the model's default, unadapted
    assert {v for _, v in m["series"]["fps"]} == {12.0}
    assert m["speed_mm_s"] < 55.0
    adaptive = experiment.run("residential", 0, "adaptive", time_cap=10.0, series=True)
    assert {v for _, v in adaptive["series"]["fps"]} != {12.0}  # BandwidthLimiting acts


def test_a_lost_stripe_without_the_recovery_policy_needs_the_user(weblab_app: None) -> None:
    m = experiment.run("residential", 0, "fixed_150", time_cap=60.0)
    assert m["stripe_losses"] >= 1 and m["user_requests"] >= 1 and m["recoveries"] == 0


def test_the_recovery_policy_recovers_a_lost_stripe(weblab_app: None) -> None:
    m = experiment.run("LAN", 0, "no_speed_policy", time_cap=40.0)
    assert m["stripe_losses"] >= 1 and m["recovery_actions"] >= 1 and m["recoveries"] >= 1


def test_a_user_spike_and_malformed_telemetry_are_survived(weblab_app: None) -> None:
    script = Script(user_spikes=[(2.0, 12.0, 8)], malformed_telemetry=[3.0, 5.0])
    m = experiment.run("LAN", 0, "adaptive", time_cap=15.0, script=script)
    assert m["users_max"] == 9  # the Navigator and 8 more
    assert m["faults"] == 2  # each malformed reading, recorded by the Telemetry monitor
    assert m["cycles"] >= 20 and m["user_requests"] == 0


def test_a_failing_recovery_action_is_a_counted_fault_and_the_run_goes_on(
    weblab_app: None,
) -> None:
    clean = experiment.run("LAN", 0, "no_speed_policy", time_cap=40.0)
    script = Script(failing_recoveries=[0.0])
    m = experiment.run("LAN", 0, "no_speed_policy", time_cap=40.0, script=script)
    assert clean["faults"] == 0 and m["faults"] == 1
    # The failed action did nothing; the next one recovered, and the robot went on.
    assert m["recovery_actions"] >= 1 and m["recoveries"] >= 1
    assert m["progress_mm"] > 2500.0


def test_an_unknown_condition_is_refused_with_the_known_ones() -> None:
    with pytest.raises(ValueError, match="fixed_50"):
        experiment.run("LAN", 0, "turbo")


@pytest.mark.slow
def test_a_run_that_lost_the_stripe_at_a_corner_ends_instead_of_recovering_in_a_loop(
    weblab_app: None,
) -> None:
    # Without the speed policy this robot overshoots the first corner on the residential link,
    # and used to follow the stripe back to its start, "recovering" there until the 400 s cap
    # (34 recoveries). Now it keeps its direction of travel and a recovery must get it ahead.
    # (Since the recovery's speed cap lasts only until the recovery succeeded, this robot is
    # back at 200 mm/s after each one, and loses the stripe at more corners: 6 losses.)
    m = experiment.run("residential", 1009, "no_speed_policy")
    assert m["finished"] == 1 and m["time_s"] < 200.0
    assert m["recoveries"] <= m["recovery_actions"] <= 3 * m["stripe_losses"]
    assert m["followed_backwards"] == 0


def test_the_sharp_path_and_any_fixed_speed_are_conditions_of_a_run(weblab_app: None) -> None:
    m = experiment.run("LAN", 0, "fixed_65", time_cap=12.0, path="sharp", series=True)
    assert {v for _, v in m["series"]["max_speed"]} == {200.0}  # every policy off
    assert 60.0 < m["speed_mm_s"] < 67.0
    with experiment.rig("LAN", 0, path="sharp") as rig:
        assert [round(t) for t in rig.lab.path.turns()] == [115, -115, 110, 70, 45]
        corner = rig.lab.path.points[1]  # the camera sees the sharp path's stripe, not the other
        rig.lab.robot.place(0.0, corner[0] - 200.0, corner[1], 0.0)
        assert detector.find_stripe(camera.encode(rig.lab.grab_frame(), 75)) > 20.0
    with pytest.raises(ValueError, match="fixed_<speed>"):
        experiment.run("LAN", 0, "fixed_5000")
    with pytest.raises(ValueError, match="paths: default, sharp, right, gentle"):
        experiment.run("LAN", 0, path="zigzag")
