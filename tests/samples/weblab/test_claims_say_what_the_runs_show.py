"""The claims on made-up tables: a tie with the recovery kept is said, never claimed (it cannot
fail the experiment); the time from campus to LAN is claimed not to rise by more than one
person's help where it is claimed at all; the recovery's own claim compares like speeds."""

from __future__ import annotations

from weblab_experiment.stats import Stat, difference
from weblab_experiment.summary import NO_SLOWER_S, SCOPES, claims
from weblab_sim.world import HUMAN_DELAY

PROFILES = ("residential", "campus", "LAN")


def cell(time_s: float, users: float = 0.0, sd: float = 1.0) -> dict[str, Stat]:
    values = {
        "time_s": Stat(time_s, sd, 5),
        "user_requests": Stat(users, 0.0, 5),
        "cycles_per_s": Stat(0.0, 0.0, 5),
        "speed_mm_s": Stat(0.0, 0.0, 5),
        "fps": Stat(0.0, 0.0, 5),
    }
    return values


def table(lan_time: float, unlimited_100: tuple[float, float, float]) -> dict:
    adaptive = {"residential": cell(115.0), "campus": cell(71.0), "LAN": cell(lan_time)}
    for p, rate, fps in zip(PROFILES, (0.85, 1.44, 1.72), (5.0, 12.0, 11.0), strict=True):
        adaptive[p]["cycles_per_s"] = Stat(rate, 0.01, 5)
        adaptive[p]["speed_mm_s"] = Stat(rate * 70, 1.0, 5)
        adaptive[p]["fps"] = Stat(fps, 0.1, 5)
    return {
        "default": {
            "adaptive": adaptive,
            "fixed_100": {p: cell(120.0, users=2.0) for p in PROFILES},
            "no_speed_policy_100": {
                p: cell(t) for p, t in zip(PROFILES, unlimited_100, strict=True)
            },
        }
    }


def by_text(found, start: str):
    return next(c for c in found if c.text.startswith(start))


def test_a_fixed_speed_with_the_recovery_kept_as_good_everywhere_is_said_not_claimed() -> None:
    found = claims(table(67.0, (100.0, 71.0, 67.0)), [], PROFILES)  # ties adaptation everywhere
    none = by_text(found, "no fixed speed (only SpeedLimiting off")
    some = by_text(found, "with the recovery kept, some fixed speed")
    assert not none.holds and none.verdict == "not shown on these runs" and not none.claimed
    assert some.holds and some.verdict == "shown on these runs" and not some.claimed
    # what decides the exit code: no claim that is made fails
    assert all(c.holds for c in found if c.claimed)


def test_campus_to_lan_is_claimed_not_to_rise_by_more_than_one_persons_help() -> None:
    assert NO_SLOWER_S == HUMAN_DELAY
    assert "default" in SCOPES["time_last_no_slower"]
    for lan, holds in ((69.0, True), (71.0 + NO_SLOWER_S + 3.0, False)):
        found = claims(table(lan, (200.0, 200.0, 200.0)), [], PROFILES)
        step = by_text(found, "adaptive: the time to the finish does not rise from campus to LAN")
        oracle = difference(Stat(lan, 1.0, 5), Stat(71.0, 1.0, 5))
        assert oracle is not None and (oracle.high < NO_SLOWER_S) == holds
        assert step.claimed and step.holds == holds


def test_the_recovery_claim_sums_the_same_speeds_of_both_families() -> None:
    found = claims(table(67.0, (200.0, 200.0, 200.0)), [], PROFILES)
    recovery = by_text(found, "with the recovery kept, the fixed speeds need the user less often")
    assert recovery.claimed and recovery.holds
    assert recovery.detail == "0.0 against 6.0, 1 speed"  # 2 requests per run on 3 profiles
