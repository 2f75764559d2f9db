"""An operation whose signature changes is one change of the plan, both signatures shown
(``~ component Display: operation watch(seconds: int) -> watch()``), not one removed and one
added: matched by its name, or else by its model id (an operation renamed, as a modelling tool
renames: its id stays). Operations that cannot be told apart (two of one name) are removed and
added as before; a port's operations alike."""

from __future__ import annotations

from dataclasses import replace

from acordcs.descriptor.diff import diff
from tests.support.descriptors import application, component, container, op, port, ref


def display(*operations, ports=()):
    return application(
        "Show",
        containers=(container("screen", ref("component", "Display")),),
        components=(component("Display", operations=tuple(operations), ports=ports),),
    )


WATCH = op("watch", ("seconds", "int", "in"))


def test_a_parameter_removed_is_one_change_showing_both_signatures():
    plan = diff(display(WATCH, op("clear")), display(op("watch"), op("clear")))
    assert plan.lines == ("~ component Display: operation watch(seconds: int) -> watch()",)
    (change,) = plan.changes
    assert change.action == "replace" and change.live and change.containers == ("screen",)


def test_types_directions_and_results_are_part_of_the_signature():
    new = op("watch", ("seconds", "double", "in"), ("seen", "int", "out"), returns="bool")
    assert diff(display(WATCH), display(new)).lines == (
        "~ component Display: operation watch(seconds: int) -> "
        "watch(seconds: double, out seen: int): bool",
    )


def test_a_renamed_operation_is_matched_by_its_id():
    renamed = replace(WATCH, name="observe")
    assert diff(display(WATCH), display(renamed)).lines == (
        "~ component Display: operation watch(seconds: int) -> observe(seconds: int)",
    )


def test_a_new_operation_of_another_id_is_removed_and_added():
    assert diff(display(WATCH), display(op("observe"))).lines == (
        "~ component Display: operation watch(seconds: int) removed",
        "~ component Display: operation observe() added",
    )


def test_two_of_one_name_are_told_apart_by_their_ids_or_else_removed_and_added():
    twice = (WATCH, replace(op("watch"), id="other"))
    after = (replace(WATCH, parameters=()), replace(op("watch", ("n", "int", "in")), id="other"))
    assert diff(display(*twice), display(*after)).lines == (
        "~ component Display: operation watch(seconds: int) -> watch()",
        "~ component Display: operation watch() -> watch(n: int)",
    )
    no_ids = [tuple(replace(o, id="") for o in ops) for ops in (twice, after)]
    assert diff(display(*no_ids[0]), display(*no_ids[1])).lines == (
        "~ component Display: operation watch(seconds: int) removed",
        "~ component Display: operation watch(n: int) added",
    )


def test_a_ports_operation_alike():
    before = display(ports=(replace(port("screenPort"), operations=(WATCH,)),))
    after = display(ports=(replace(port("screenPort"), operations=(op("watch"),)),))
    assert diff(before, after).lines == (
        "~ component Display: port screenPort: operation watch(seconds: int) -> watch()",
    )
