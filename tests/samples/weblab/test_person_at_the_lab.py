"""The lab's person (:class:`weblab_sim.experiment.Person`) steps in after missed cycles and after
repeated recoveries at the same place, and not otherwise."""

from __future__ import annotations

from types import SimpleNamespace

from weblab_sim.experiment import PATIENCE, REPEATS, SAME_PLACE_MM, Person


class Recovery:
    def __init__(self) -> None:
        self.instance = SimpleNamespace(actions=0)
        self.asked = 0

    def askUser(self) -> None:
        self.asked += 1


def person() -> tuple[Person, SimpleNamespace, Recovery, SimpleNamespace]:
    nav = SimpleNamespace(instance=SimpleNamespace(misses_in_row=0, cycles=[]))
    recovery, lab = Recovery(), SimpleNamespace(progress=0.0)
    return Person(nav, recovery, lab), nav, recovery, lab


def test_recoveries_that_get_the_robot_on_do_not_bring_the_person() -> None:
    watcher, _nav, recovery, lab = person()
    for _ in range(3 * REPEATS):
        recovery.instance.actions += 1
        lab.progress += SAME_PLACE_MM  # each recovery, and the robot gets on
        watcher.look()
    assert recovery.asked == 0


def test_repeated_recoveries_at_the_same_place_bring_the_person() -> None:
    watcher, _nav, recovery, lab = person()
    lab.progress = 2000.0
    watcher.look()
    for n in range(1, REPEATS + 1):
        recovery.instance.actions += 1
        lab.progress += SAME_PLACE_MM / (REPEATS + 1)  # "recovered", but never far
        watcher.look()
        assert recovery.asked == (1 if n == REPEATS else 0)
    watcher.look()  # the count starts again where the person left the robot
    assert recovery.asked == 1


def test_cycles_without_stripe_bring_the_person_once_per_patience() -> None:
    watcher, nav, recovery, _lab = person()
    nav.instance.misses_in_row = PATIENCE - 1
    watcher.look()
    assert recovery.asked == 0
    nav.instance.misses_in_row = PATIENCE
    nav.instance.cycles = [None] * 10
    watcher.look()
    watcher.look()  # not again before PATIENCE more cycles
    assert recovery.asked == 1
    nav.instance.cycles += [None] * PATIENCE
    watcher.look()
    assert recovery.asked == 2
