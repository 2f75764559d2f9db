"""How figures are shown, in the printed tables and in report.html alike: each metric with its own
number of decimals (no digit finer than the runs can tell apart), mean ± sample SD with the SD
left out where it rounds to 0, and differences with their 95% interval."""

from __future__ import annotations

from weblab_experiment.stats import Difference, Stat

DIGITS = {
    "cycles_per_s": 2,
    "speed_mm_s": 0,
    "time_s": 0,
    "recoveries": 1,
    "recovery_actions": 1,
    "stripe_losses": 1,
    "losses_near_corner": 1,
    "user_requests": 1,
    "fps": 1,
    "fps_raw": 2,
    "fps_mode": 0,
    "fps_mode_share": 2,
    "mm_per_cycle": 0,
    "moving_mm": 0,
    "stopped_s": 0,
    "finished": 2,
    "faults": 0,
    "backwards_mm": 0,
    "followed_backwards": 2,
}
HEADERS = {
    "cycles_per_s": "cycles/s",
    "speed_mm_s": "speed mm/s",
    "time_s": "time s",
    "recoveries": "recov.",
    "stripe_losses": "losses",
    "user_requests": "user req.",
    "fps": "fps",
    "mm_per_cycle": "mm/cycle",
    "faults": "faults",
    "finished": "finished",
}
"""Column headers (results.json and results.csv keep the plain metric names)."""
TABLE_METRICS = (
    "cycles_per_s",
    "speed_mm_s",
    "time_s",
    "recoveries",
    "stripe_losses",
    "user_requests",
    "fps",
    "faults",
)
"""The metrics of the every-condition table (``finished`` is shown as runs finished of n)."""
TABLE_1 = ("cycles_per_s", "speed_mm_s", "time_s", "recoveries", "fps")


def number(value: float, digits: int) -> str:
    """``value`` with ``digits`` decimals, never "-0"."""
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def paper(value: float, metric: str) -> str:
    """A Table-1 figure as the paper prints it (cycle rates with two decimals, the rest whole)."""
    return number(value, 2) if metric == "cycles_per_s" else f"{value:g}"


def mean_sd(stat: Stat, metric: str) -> str:
    """``mean ± SD`` at the metric's decimals; the SD left out where it rounds to 0."""
    digits = DIGITS.get(metric, 2)
    shown = number(stat.mean, digits)
    if stat.n > 1 and float(number(stat.sd, digits)) != 0:
        shown += f" ± {number(stat.sd, digits)}"
    return shown


def mean(stat: Stat, metric: str) -> str:
    return number(stat.mean, DIGITS.get(metric, 2))


def finished(stat: Stat) -> str:
    """Runs that reached the finish line, of the cell's runs."""
    return f"{round(stat.mean * stat.n)}/{stat.n}"


def interval(diff: Difference | None, digits: int = 0) -> str:
    """``+x [low, high]`` (signed), or "n < 2" when there is no interval."""
    if diff is None:
        return "n < 2"

    def signed(v: float) -> str:
        text = number(v, digits)
        return text if text.startswith("-") or float(text) == 0 else "+" + text

    return f"{signed(diff.estimate)} [{signed(diff.low)}, {signed(diff.high)}]"
