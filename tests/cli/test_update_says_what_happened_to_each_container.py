"""What ``acordcs-gen update`` says of the containers it finds is what happened (issue 36, item
7): a container stopped with SIGSTOP takes connections but answers nothing, and is said not to
answer within the timeout, not to be "not running"; one that is gone is not running; containers
on different descriptors are said to be so, not to have rolled a part back (nothing was rolled
back: an earlier update reached only some of them, or they were started from other builds)."""

from __future__ import annotations

import signal
from types import SimpleNamespace

import pytest

from acordcs.cli.running import reach
from acordcs.cli.update import show_plans
from acordcs.runtime.live.app_settings import Settings
from tests.support.managed_container import served_house

TOKEN = "token-of-the-house"


@pytest.fixture
def house(tmp_path):
    """The container ``house`` served (with its management interface) in a child process:
    (its process, its port)."""
    with served_house(tmp_path / "house.log", TOKEN) as (child, port):
        yield child, port


def problem(port: int) -> str:
    found = Settings("run", TOKEN, "pkg", {"house": ("127.0.0.1", str(port))})
    (reached,) = reach(found, timeout=1.0)
    return reached.problem


def test_a_frozen_container_does_not_answer_within_the_timeout_a_gone_one_is_not_running(house):
    child, port = house
    assert problem(port) == ""
    child.send_signal(signal.SIGSTOP)
    try:
        frozen = problem(port)
    finally:
        child.send_signal(signal.SIGCONT)
    # the handshake or the status call found it frozen (a race): the same words either way
    assert frozen.startswith("it does not answer within the timeout (")
    assert "receiving: timeout" in frozen
    assert "takes connections but answers none" in frozen and "kill -CONT" in frozen
    assert "not running" not in frozen
    assert problem(port) == ""  # resumed: it answers again
    child.stdin.close()
    child.wait(20)
    assert problem(port).startswith("not running (nothing answers: cannot connect to")


def test_containers_on_different_descriptors_are_not_said_to_have_rolled_back(capsys):
    def running(name: str, digest: str) -> SimpleNamespace:
        return SimpleNamespace(name=name, host="127.0.0.1", port="1", status={"digest": digest})

    plan = SimpleNamespace(changes=())
    show_plans(
        [running("A", "a" * 64), running("B", "b" * 64)], {"A": plan, "B": plan}, {"A": (), "B": ()}
    )
    out = capsys.readouterr().out
    assert "on different descriptors (an earlier update reached only some of them" in out
    assert "rolled back" not in out
