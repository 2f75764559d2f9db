"""What ``acordcs-gen update`` says of the containers it finds is what happened (issue 36, item
7): a container stopped with SIGSTOP takes connections but answers nothing, and is said not to
answer within the timeout, not to be "not running"; one that is gone is not running; containers
on different descriptors are said to be so, not to have rolled a part back (nothing was rolled
back: an earlier update reached only some of them, or they were started from other builds)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from types import SimpleNamespace

import pytest

from acordcs.cli.running import Settings, reach
from acordcs.cli.update import _show
from tests.support.toolchain import ROOT

TOKEN = "token-of-the-house"


@pytest.fixture
def house(tmp_path):
    """The container ``house`` served (with its management interface) in a child process:
    (its process, its port)."""
    log = tmp_path / "house.log"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    env.pop("ACORDCS_TOKEN", None)
    with log.open("wb") as out:
        child = subprocess.Popen(
            [sys.executable, "-m", "tests.support.managed_container", TOKEN],
            cwd=ROOT,
            env=env,
            stdin=subprocess.PIPE,
            stdout=out,
            stderr=subprocess.STDOUT,
        )
    try:
        deadline = time.monotonic() + 60
        while not (found := re.search(r"READY (\d+)", log.read_text())):
            assert child.poll() is None, log.read_text()
            assert time.monotonic() < deadline, "the container did not start within 60 s"
            time.sleep(0.05)
        yield child, int(found.group(1))
    finally:
        child.send_signal(signal.SIGCONT)
        assert child.stdin is not None
        child.stdin.close()
        try:
            child.wait(20)
        except subprocess.TimeoutExpired:
            child.kill()
            child.wait(5)


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
    assert frozen.startswith("it does not answer within the timeout (receiving: timeout)")
    assert "takes connections but answers none" in frozen and "kill -CONT" in frozen
    assert "not running" not in frozen
    assert problem(port) == ""  # resumed: it answers again
    child.stdin.close()
    child.wait(20)
    assert problem(port).startswith("not running (nothing answers: cannot connect to")


def test_containers_on_different_descriptors_are_not_said_to_have_rolled_back(capsys):
    def running(name: str, digest: str) -> SimpleNamespace:
        return SimpleNamespace(name=name, host="127.0.0.1", port="1", status={"digest": digest})

    plan = SimpleNamespace(changes=[])
    _show([running("A", "a" * 64), running("B", "b" * 64)], {"A": plan, "B": plan})
    out = capsys.readouterr().out
    assert "on different descriptors (an earlier update reached only some of them" in out
    assert "rolled back" not in out
