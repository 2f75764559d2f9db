"""``--run COMPONENT.OPERATION(ARGUMENTS)`` (acordcs.runtime.run_arguments): the arguments are read
as literals, never evaluated, and typed by the operation's parameters in the model (int, double,
bool, string, as the descriptor's value kinds), by position or by name. What does not fit is
refused with what, which parameter, its type and what to write: a value of another kind, too many
or too few arguments, a name that is no parameter; what is no value at all (code, a name, a list),
numbers no parameter holds (a million digits, NaN, infinity, beyond a double) are refused before
any work is done on them."""

from __future__ import annotations

import time

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.descriptor.application import Operation, Parameter
from acordcs.runtime.run_arguments import MAX_TEXT, RunError, bind_run, parse_run

WATCH = Operation("w", "watch", "D::watch", (Parameter("p1", "seconds", "int"),))
SHOW = Operation(
    "s",
    "show",
    "D::show",
    (
        Parameter("p1", "text", "String"),
        Parameter("p2", "size", "double"),
        Parameter("p3", "bold", "boolean"),
        Parameter("p4", "shown", "int", "out"),  # not an argument: a result
    ),
)
GRAB = Operation("g", "findStripe", "D::findStripe", (Parameter("p1", "frame", "Image"),))


def run(text: str, operation: Operation | None):
    return bind_run(parse_run(text), operation)


def refused(text: str, operation: Operation | None = WATCH) -> str:
    with pytest.raises(RunError) as caught:
        run(text, operation)
    return str(caught.value)


@pytest.mark.parametrize(
    ("text", "operation", "values", "shown"),
    [
        ("Display.watch(5)", WATCH, (5,), "Display.watch(5)"),
        ("Display.watch(-3)", WATCH, (-3,), "Display.watch(-3)"),
        ("Display.watch(seconds=7)", WATCH, (7,), "Display.watch(7)"),
        (" Display.watch ( 4 ) ", WATCH, (4,), "Display.watch(4)"),
        ("Display.show('a, b', 2, TRUE)", SHOW, ("a, b", 2.0, True), "Display.show('a, b', 2.0, true)"),
        ('Display.show("it\'s \\"q\\"\\n", 1e-3, false)', SHOW, ('it\'s "q"\n', 0.001, False), None),
        ("Display.show(bold=false, size=.5, text='x')", SHOW, ("x", 0.5, False), None),
        ("Display.show('x', size=2.5, bold=true)", SHOW, ("x", 2.5, True), None),
        ("Nav.step", None, (), "Nav.step()"),
        ("Nav.step(1, 'x')", None, (1, "x"), "Nav.step(1, 'x')"),  # not in the model: as written
    ],
)  # fmt: skip
def test_arguments_are_typed_by_the_parameters(text, operation, values, shown):
    call = run(text, operation)
    assert call.values == values
    assert [type(v) for v in call.values] == [type(v) for v in values]
    if shown is not None:
        assert call.text == shown


@pytest.mark.parametrize(
    ("text", "operation", "says"),
    [
        ("Display.watch", WATCH, "--run Display.watch: Display.watch(seconds: int) takes 1 argument, 0 given: give seconds (int), as Display.watch(5)"),
        ("Display.watch(5, 6)", WATCH, "--run Display.watch(5, 6): Display.watch(seconds: int) takes 1 argument, 2 given: give one value per parameter, in order"),
        ("Display.watch(five)", WATCH, "--run Display.watch(five): argument 1 of watch, parameter seconds (int): 'five' is not a value: write a number, true or false, or a string in quotes (nothing is evaluated)"),
        ("Display.watch('5')", WATCH, "argument 1 of watch, parameter seconds (int): '5' is not an int: write a whole number (5, -3)"),
        ("Display.watch(5.5)", WATCH, "parameter seconds (int): 5.5 is not an int: write a whole number"),
        ("Display.watch(true)", WATCH, "parameter seconds (int): true is not an int"),
        ("Display.watch(nan)", WATCH, "parameter seconds (int): nan is not a finite number: write a finite number"),
        ("Display.show('a', NaN, true)", SHOW, "argument 2 of show, parameter size (double): NaN is not a finite number"),
        ("Display.show('a', -inf, true)", SHOW, "parameter size (double): -inf is not a finite number"),
        ("Display.show('a', 1e999, true)", SHOW, "parameter size (double): 1e999 is beyond a double's range"),
        ("Display.show(5, 1, true)", SHOW, "parameter text (String): 5 is not a string: write a string in quotes"),
        ("Display.show('a', 1, 1)", SHOW, "parameter bold (boolean): 1 is not a bool: write true or false"),
        ("Display.watch(1" + "0" * 19 + ")", WATCH, "has more than 19 characters, more than an int of the descriptor holds"),
        ("Display.watch(" + "9" * 41 + ")", WATCH, "a number of more than 40 characters: write one of at most 40"),
        ("Display.watch(secs=3)", WATCH, "Display.watch(seconds: int) has no parameter 'secs': name one of seconds"),
        ("Display.watch(5, seconds=3)", WATCH, "parameter seconds is given twice"),
        ("Display.findStripe(1)", GRAB, "parameter frame (Image): a value of type Image cannot be written on a command line (int, double, bool and string can): call the operation from your code"),
        ("Nav.step(x=1)", None, "the model declares no operation step of Nav, so its parameters have no names"),
    ],
)  # fmt: skip
def test_what_does_not_fit_says_what_which_parameter_and_what_to_write(text, operation, says):
    assert says in refused(text, operation)


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("Display", "'Display' is not COMPONENT.OPERATION or COMPONENT.OPERATION(ARGUMENTS)"),
        ("Display.watch(5", "no ')' at the end: close the arguments"),
        ("Display.watch(5,", "an argument is missing before the end"),
        ("Display.watch(5,)", "an argument is missing before ')'"),
        ("Display.watch(,5)", "an argument is missing before ','"),
        ("Display.watch(5) x", "' x' after the closing ')'"),
        ("Display.watch(5)(6)", "'(6)' after the closing ')'"),
        ("Display.watch('abc)", "a string is not closed: end it with '"),
        ("Display.watch(x=1, 2)", "an argument by position after one by name"),
        ("Display.watch(__import__('os').system('touch pwned'))", "is not a value"),
        ("Display.watch(lambda: 1)", "'lambda: 1' is not a value"),
        ("Display.watch([1])", "'[1]' is not a value"),
        ("Display.watch({1: 2})", "is not a value"),
        ("Display.watch(1 + 1)", "'1 + 1' is not a value"),
        ("Display.watch(0x10)", "'0x10' is not a value"),
        ("Display.watch(f'{x}')", "is not a value"),
        ("Display.watch(b'x')", "is not a value"),
        ("Display.watch(5)" + " " * MAX_TEXT, f"a --run has at most {MAX_TEXT}"),
    ],
)
def test_what_is_no_call_of_literals_is_refused_as_written(text, says):
    assert says in refused(text)


def test_a_million_digits_cost_nothing_to_refuse():
    began = time.perf_counter()
    message = refused("Display.watch(" + "9" * 10**6 + ")")
    assert time.perf_counter() - began < 0.5
    assert f"1000015 characters: a --run has at most {MAX_TEXT}" in message
    assert len(message) < 300  # the text is not echoed whole


@given(st.text(max_size=60))
@settings(max_examples=300, deadline=None)
def test_any_text_is_read_or_refused_never_evaluated(text):
    try:
        call = run(f"Display.show({text})", SHOW)
    except RunError:
        return
    assert [type(v) for v in call.values] == [str, float, bool]


@given(
    st.text(max_size=20),
    st.floats(allow_nan=False, allow_infinity=False),
    st.booleans(),
)
@settings(max_examples=200, deadline=None)
def test_values_written_as_literals_come_back_as_they_were(text, size, bold):
    call = run(f"Display.show({text!r}, {size!r}, {str(bold).lower()})", SHOW)
    assert call.values == (text, size, bold)
