"""From runs to results: each metric's mean, sample standard deviation and n per (path,
condition, profile), and the claims the reproduction must hold, each checked, per path.

The claims: every run of every condition finishes (a run that hits the time cap is a failure);
the orderings of Table 1 across profiles for the adaptive runs (each step's 95% Welch interval on
its side of 0); no user request with adaptation
on the default path, fewer than with any fixed speed on the others (:data:`STRICT`);
the fast fixed speed (150 mm/s, chosen beforehand) needs the user on every profile; against the
fixed speeds of the sweep: adaptation is faster (95% Welch interval of the difference of the mean
times below 0) than every fixed speed that needs no user on that profile, and no fixed speed is as
good as adaptation on every profile (each is slower, by that interval, or needs the user somewhere).
"""

from __future__ import annotations

import itertools
from collections import defaultdict
from dataclasses import dataclass, replace

from weblab_sim.experiment import BACKWARDS_MM, FIXED, UNLIMITED, family, fixed_speed

from weblab_experiment.display import interval
from weblab_experiment.grid import Outcome
from weblab_experiment.stats import Difference, Stat, difference

METRICS = (
    "cycles_per_s",
    "speed_mm_s",
    "time_s",
    "recoveries",
    "recovery_actions",
    "stripe_losses",
    "losses_near_corner",
    "user_requests",
    "fps",
    "fps_raw",
    "fps_mode",
    "fps_mode_share",
    "mm_per_cycle",
    "moving_mm",
    "stopped_s",
    "finished",
    "faults",
    "backwards_mm",
    "followed_backwards",
)
"""The metrics summarised (plain names, as in results.json and results.csv)."""

PAPER = {
    # Table 1 of the paper (Dell D520 notebook, 2 GB RAM): cycles/s, speed mm/s, time s,
    # recoveries, fps.
    "residential": {
        "cycles_per_s": 0.90,
        "speed_mm_s": 69,
        "time_s": 124,
        "recoveries": 4,
        "fps": 4,
    },
    "campus": {"cycles_per_s": 1.46, "speed_mm_s": 127, "time_s": 99, "recoveries": 12, "fps": 12},
    "LAN": {"cycles_per_s": 1.72, "speed_mm_s": 143, "time_s": 84, "recoveries": 8, "fps": 12},
}
FAST = "fixed_150"  # the fast fixed speed, chosen beforehand
FAMILIES = {
    FIXED: "every policy off",
    UNLIMITED: "only SpeedLimiting off, Recovering and BandwidthLimiting on",
}
"""The fixed-speed families the sweep runs, and what each switches off: the first compares
adaptation as a whole with a fixed speed, the second speed adaptation alone."""
STRICT = ("default", "gentle")
"""Paths on which adaptation must need the user in no run. On the sharp path (a corner of 115
degrees turns the stripe out of the camera's view before the robot reaches it) it must need the
user less often than every fixed speed with every policy off, on every profile (:data:`SCOPES`)."""
SCOPES = {
    "fewer_user_requests": ("sharp",),
    "time_first_step": ("default", "right", "gentle"),
    "time_last_step": ("gentle",),
    "fast_needs_user": ("default", "sharp", "right"),
    "faster_than_safe_fixed": ("default", "sharp"),
    "safe_unlimited_as_fast": ("default", "right", "gentle"),
    "none_as_good_unlimited": ("sharp", "right"),
}
"""Where a claim is made, for the claims that do not hold on every path of the family (set from
the runs on seeds 0 to 2, or 0 to 9 for the default path, and checked on seeds never run while
developing: seeds 3000 to 3004 on all four paths). Elsewhere the output shows the same figures
as "not claimed here". Two scopes were narrowed after that check, and are not checked on unseen
seeds since: the time from campus to LAN (on the default path it fell by 3 s [-8, +3], a tie) and
no fixed speed with the recovery kept as good as adaptation everywhere (on the default path one
was). Why each is where it is: on the right-angle path adaptation needs the user at the second corner (the robot
overshoots it and the lab stops it on a segment far ahead), so a fixed speed that needs no user
ties it there on the LAN, and on campus and LAN some fixed speeds need no user; on the sharp
and right-angle paths the time from campus to LAN falls by less than its interval, and on the
sharp path the time from residential to campus varies with the runs that need the user; on the
gentle path 150 mm/s needs the user rarely on the LAN, a fixed 60 mm/s ties adaptation on
residential, and with the recovery kept 150 mm/s is as good as adaptation on every profile; on
the sharp path every fixed speed with the recovery kept needs the user somewhere."""
Table = dict[str, dict[str, dict[str, dict[str, Stat]]]]
"""path -> condition -> profile -> metric -> Stat."""


@dataclass(frozen=True)
class Claim:
    path: str
    text: str
    holds: bool
    detail: str
    claimed_on: tuple[str, ...] | None = None  # None: every path; else the paths it is made on

    @property
    def claimed(self) -> bool:
        """Whether the claim is made on this path (elsewhere it is shown, not claimed)."""
        return self.claimed_on is None or self.path in self.claimed_on

    @property
    def verdict(self) -> str:
        if self.claimed:
            return "holds" if self.holds else "DOES NOT HOLD"
        where = ", ".join(self.claimed_on or ())
        return f"not claimed here (made on {where} only; {'true' if self.holds else 'false'} here)"


def summarise(outcomes: list[Outcome]) -> Table:
    """path -> condition -> profile -> metric -> Stat, over the runs that did not fail."""
    values: dict[tuple[str, str, str], dict[str, list[float]]] = defaultdict(
        lambda: defaultdict(list)
    )
    for o in outcomes:
        if o.error is None:
            cell = values[o.task.path, o.task.condition, o.task.profile]
            for metric in METRICS:
                cell[metric].append(float(o.metrics[metric]))
    out: Table = {}
    for (path, condition, profile), by_metric in values.items():
        out.setdefault(path, {}).setdefault(condition, {})[profile] = {
            m: Stat.of(v) for m, v in by_metric.items()
        }
    return out


def fixed_conditions(
    by_condition: dict[str, dict[str, dict[str, Stat]]], prefix: str = FIXED
) -> list[str]:
    """The fixed-speed conditions of a path's table of one family (``prefix``), slowest first."""
    return sorted(
        (c for c in by_condition if family(c) == prefix),
        key=lambda c: fixed_speed(c) or 0.0,
    )


def sweep_verdicts(
    by_condition: dict[str, dict[str, dict[str, Stat]]],
    profiles: tuple[str, ...],
    prefix: str = FIXED,
) -> dict[str, dict[str, Difference | None]]:
    """fixed condition of the family ``prefix`` -> profile -> the Welch interval of adaptive
    minus fixed time (s)."""
    adaptive = by_condition.get("adaptive", {})
    out: dict[str, dict[str, Difference | None]] = {}
    for c in fixed_conditions(by_condition, prefix):
        out[c] = {
            p: difference(adaptive[p]["time_s"], by_condition[c][p]["time_s"])
            for p in profiles
            if p in adaptive and p in by_condition[c]
        }
    return out


def claims(table: Table, outcomes: list[Outcome], profiles: tuple[str, ...]) -> list[Claim]:
    """The reproduction's claims for each path, each with whether it holds and the figures."""
    out: list[Claim] = []
    for path, by_condition in table.items():
        out += _claims_of_path(path, by_condition, outcomes, profiles)
    return out


def _claims_of_path(
    path: str,
    table: dict[str, dict[str, dict[str, Stat]]],
    outcomes: list[Outcome],
    profiles: tuple[str, ...],
) -> list[Claim]:
    out: list[Claim] = []
    adaptive = table.get("adaptive", {})
    mine = [o for o in outcomes if o.task.path == path]
    stuck = [o for o in mine if o.error is None and not o.metrics["finished"]]
    failed = [o for o in mine if o.error is not None]
    bad = ", ".join(
        f"{o.task.condition} {o.task.profile} seed {o.task.seed}" for o in [*stuck, *failed]
    )
    caps = "/".join(sorted({f"{o.task.time_cap:g}" for o in mine}))
    out.append(
        Claim(
            path,
            f"every run of every condition finishes within the {caps} s cap",
            not stuck and not failed,
            f"{len(mine) - len(stuck) - len(failed)} of {len(mine)} runs finished"
            + (f"; {len(stuck)} hit the cap, {len(failed)} failed: {bad}" if bad else ""),
        )
    )

    ran = [o for o in mine if o.error is None]
    backwards = [o for o in ran if o.metrics["followed_backwards"]]
    worst = max(ran, key=lambda o: o.metrics["backwards_mm"], default=None)
    out.append(
        Claim(
            path,
            "no run of any condition drives the stripe backwards (more than "
            f"{BACKWARDS_MM:.0f} mm back along it while driven forward)",
            not backwards,
            f"{len(ran) - len(backwards)} of {len(ran)} runs did not"
            + (
                f"; the most: {worst.metrics['backwards_mm']:.0f} mm ({worst.task.condition} "
                f"{worst.task.profile} seed {worst.task.seed})"
                if worst is not None
                else ""
            ),
        )
    )

    def ordered(
        metric: str, what: str, rising: bool, digits: int, between: tuple[str, ...] = profiles
    ) -> Claim:
        cells = [adaptive[p][metric] for p in between if p in adaptive]
        steps = [difference(b, a) for a, b in itertools.pairwise(cells)]
        want = "higher" if rising else "lower"
        if all(d is not None for d in steps):  # each step's 95% interval on the right side of 0
            holds = all(d.verdict == want for d in steps if d is not None)
            how = "steps " + ", ".join(interval(d, digits) for d in steps)
        else:  # fewer than two runs a cell: the means alone
            holds = all((a.mean < b.mean) == rising for a, b in itertools.pairwise(cells))
            how = "n < 2: means only"
        return Claim(
            path,
            f"adaptive: {what} {'rises' if rising else 'falls'} from {' to '.join(between)} "
            "(95% interval of each step)",
            len(cells) == len(between) and holds,
            (" < " if rising else " > ").join(f"{c.mean:.{digits}f}" for c in cells) + f"; {how}",
        )

    if len(profiles) > 1 and adaptive:
        out += [
            ordered("cycles_per_s", "the cycle rate", True, 2),
            ordered("speed_mm_s", "the speed", True, 0),
        ]
        shown = [p for p in profiles if p in adaptive]
        for i, (a, b) in enumerate(itertools.pairwise(shown)):
            step = ordered("time_s", "the time to the finish", False, 0, (a, b))
            key = "time_last_step" if b == "LAN" else "time_first_step" if i == 0 else None
            out.append(replace(step, claimed_on=SCOPES[key]) if key else step)
        if "residential" in profiles:
            fps = {p: adaptive[p]["fps"].mean for p in profiles if p in adaptive}
            out.append(
                Claim(
                    path,
                    "adaptive: the panorama's frame rate is lowest on residential",
                    "residential" in fps
                    and all(fps["residential"] < v for p, v in fps.items() if p != "residential"),
                    ", ".join(f"{p} {v:.1f} fps" for p, v in fps.items()),
                )
            )
    fixed = fixed_conditions(table)
    if adaptive and (path in STRICT or not fixed):
        requests = {p: adaptive[p]["user_requests"].mean for p in profiles if p in adaptive}
        out.append(
            Claim(
                path,
                "adaptive: no run needs the user",
                all(v == 0 for v in requests.values()),
                ", ".join(f"{p} {v:.1f} per run" for p, v in requests.items()),
            )
        )
    elif adaptive:
        least = {
            p: min(table[c][p]["user_requests"].mean for c in fixed if p in table[c])
            for p in profiles
            if p in adaptive and any(p in table[c] for c in fixed)
        }
        out.append(
            Claim(
                path,
                "adaptive: needs the user less often than every fixed speed with every policy off, "
                "on every profile",
                all(adaptive[p]["user_requests"].mean < v for p, v in least.items()),
                ", ".join(
                    f"{p} {adaptive[p]['user_requests'].mean:.1f} against at least {v:.1f} "
                    "requests per run"
                    for p, v in least.items()
                ),
                SCOPES["fewer_user_requests"],
            )
        )
    fast = table.get(FAST, {})
    if fast:
        requests = {p: fast[p]["user_requests"].mean for p in profiles if p in fast}
        out.append(
            Claim(
                path,
                f"{FAST} (150 mm/s, chosen beforehand) needs the user on every profile",
                all(v > 0 for v in requests.values()),
                ", ".join(f"{p} {v:.1f} per run" for p, v in requests.items()),
                SCOPES["fast_needs_user"],
            )
        )
    if adaptive:
        for prefix in FAMILIES:
            if fixed_conditions(table, prefix):
                out += _sweep_claims(path, table, profiles, prefix)
    return out


def _sweep_claims(
    path: str,
    table: dict[str, dict[str, dict[str, Stat]]],
    profiles: tuple[str, ...],
    prefix: str,
) -> list[Claim]:
    verdicts = sweep_verdicts(table, profiles, prefix)
    which = f"fixed speed ({FAMILIES[prefix]})"
    safe: list[str] = []  # (fixed speed, profile) that needs no user, and how adaptation did
    faster = True
    for c, by_profile in verdicts.items():
        for p, diff in by_profile.items():
            if table[c][p]["user_requests"].mean > 0:
                continue
            faster &= diff is not None and diff.verdict == "lower"
            safe.append(
                f"{p} {c}: {diff.estimate:+.0f} s [{diff.low:+.0f}, {diff.high:+.0f}]"
                if diff is not None
                else f"{p} {c}: no interval (n < 2)"
            )
    figures = "; ".join(safe) if safe else f"every {which} needed the user on every profile"
    matched: list[str] = []  # fixed speeds as good as adaptation everywhere
    for c, by_profile in verdicts.items():
        worse = any(
            table[c][p]["user_requests"].mean > 0 or (d is not None and d.verdict == "lower")
            for p, d in by_profile.items()
        )
        if not worse:
            matched.append(c)
    if prefix == FIXED:
        speed_claim = Claim(
            path,
            f"adaptation is faster than every {which} that needs no user on that profile (95% "
            "interval of adaptive minus fixed time below 0)",
            faster,
            figures,
            SCOPES["faster_than_safe_fixed"],
        )
    else:
        speed_claim = Claim(
            path,
            f"with the recovery kept, a fixed speed can match adaptation: some {which} that "
            "needs no user is as fast on some profile (95% interval of adaptive minus fixed time "
            "not below 0)",
            bool(safe) and not faster,
            figures,
            SCOPES["safe_unlimited_as_fast"],
        )
    return [
        speed_claim,
        Claim(
            path,
            f"no {which} is as good as adaptation on every profile (each is slower by that "
            "interval, or needs the user, somewhere)",
            not matched,
            f"{len(verdicts)} fixed speeds ({', '.join(verdicts)})"
            + (f"; as good everywhere: {', '.join(matched)}" if matched else ""),
            None if prefix == FIXED else SCOPES["none_as_good_unlimited"],
        ),
    ]
