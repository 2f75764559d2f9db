"""What a viewer sends the console of an application is read strictly (issue 31): a ``call``
names an operation of a provided synchronous port of the model with arguments of its parameters'
types, a ``set`` a component's property with a value of its type, range checks before any
arithmetic; every hostile message is a CommandError saying why, never another exception."""

from __future__ import annotations

import json

import pytest

from acordcs.console.app_commands import parse
from acordcs.console.page_model import page_model
from acordcs.console.viewer_messages import CommandError
from acordcs.descriptor import from_xml
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from tests.support.toolchain import SAMPLES


@pytest.fixture(scope="module")
def page():
    from acordcs.descriptor import to_xml

    app = describe(read_model(SAMPLES / "papyrus" / "ventilation.uml").architecture)
    return page_model(from_xml(to_xml(app)))


def read(page, message) -> object:
    text = message if isinstance(message, str) else json.dumps(message)
    return parse(text, page["operations"], page["properties"])


def test_a_call_of_the_models_operation_is_read_with_its_arguments_typed(page):
    command = read(page, {"cmd": "call", "component": "Fan", "port": "FanPort",
                          "operation": "setSpeed", "args": [55], "ref": 7})  # fmt: skip
    assert (command.name, command.args, command.echo) == (
        "call",
        {"component": "Fan", "port": "FanPort", "operation": "setSpeed", "args": [55.0]},
        {"ref": 7},
    )
    assert isinstance(command.args["args"][0], float)


def test_a_property_of_a_component_is_set_with_a_value_of_its_type(page):
    command = read(page, {"cmd": "set", "element": "Fan", "attribute": "filterHours", "value": 3})
    assert command.args == {"element": "Fan", "attribute": "filterHours", "value": 3}


@pytest.mark.parametrize(
    ("message", "said"),
    [
        ({"cmd": "call", "component": "Panel", "port": "PanelPort", "operation": "boost"},
         "not an operation of a provided synchronous port"),  # a required port's
        ({"cmd": "call", "component": "Fan", "port": "FanPort", "operation": "setSpeed",
          "args": [10**400]}, "finite number"),
        ({"cmd": "call", "component": "Fan", "port": "FanPort", "operation": "setSpeed",
          "args": [True]}, "finite number"),
        ({"cmd": "call", "component": "Fan", "port": "FanPort", "operation": "setSpeed",
          "args": []}, "list of 1 value"),
        ({"cmd": "call", "component": "Fan", "port": "FanPort", "operation": "__init__"},
         "not an operation"),
        ({"cmd": "call", "component": "Fan;rm", "port": "FanPort", "operation": "purge"},
         "the model's names"),
        ({"cmd": "set", "element": "Fan", "attribute": "filterHours", "value": 2**64},
         "integer of at most 64 bits"),
        ({"cmd": "set", "element": "Fan", "attribute": "filterHours", "value": 1.5},
         "integer of at most 64 bits"),
        ({"cmd": "set", "element": "Fan", "attribute": "__class__", "value": 1},
         "not a property"),
        ({"cmd": "apply", "plan": "../../etc"}, "sha256"),
        ({"cmd": "ping", "ref": -1}, "'ref'"),
        ({"cmd": "drive"}, "unknown command"),
        ("[" * 3000, "not JSON"),
        ("x" * 5000, "at most 4096"),
    ],
)  # fmt: skip
def test_every_hostile_message_is_refused_saying_why(page, message, said):
    with pytest.raises(CommandError, match=said.replace("(", r"\(")):
        read(page, message)
