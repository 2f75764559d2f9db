"""``bin/start-host HOST`` and ``bin/stop-host HOST`` (the ``shell`` target, shell-hosts.xsl): the
containers the model places on HOST (or whose ``ACORDCS_<C>_HOST`` setting is HOST) start, with
their address and port, and no other; a missing or unknown HOST is a usage error (exit 2) listing
the hosts. The WebLab's two containers (user.example.org, weblab.example.org), run by the fake
container module (no runtime: the scripts are under test)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support import fake_container
from tests.support.generator import build
from tests.support.toolchain import WEBLAB

CONTAINERS = ("UserSide", "WebLabSide")


@pytest.fixture(scope="module")
def app(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("hosts") / "out"
    result = build(WEBLAB, out, "-t", "python,shell")
    assert result.code == 0, result.err
    fake_container.install(out, "weblab_app", CONTAINERS)
    return out


def run(app: Path, env: dict[str, str], script: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["sh", str(app / "bin" / script), *args], env=env, capture_output=True,
                          text=True, timeout=60)  # fmt: skip


@pytest.fixture
def env(app: Path, tmp_path: Path):
    settings = {
        **{k: v for k, v in os.environ.items() if not k.startswith("ACORDCS_")},
        "PYTHON": sys.executable,
        "ACORDCS_RUN_DIR": str(tmp_path / "run"),
        "ACORDCS_TOKEN": "t" * 32,
        "ACORDCS_WebLabSide_HOST": "127.0.0.2",  # an address for the model's weblab.example.org
        "FAKE_ARGS": str(tmp_path / "args"),
    }
    yield settings
    run(app, settings, "stop-all")


def test_start_host_starts_that_hosts_container_only(app: Path, env: dict[str, str]) -> None:
    started = run(app, env, "start-host", "weblab.example.org")
    assert started.returncode == 0, started.stderr
    assert run(app, env, "WebLabSide-status").returncode == 0
    assert run(app, env, "UserSide-status").returncode == 3  # not running, never started
    given = Path(env["FAKE_ARGS"]).read_bytes().split(b"\0")
    assert given[given.index(b"--host") + 1] == b"127.0.0.2"  # its setting, not the model's name
    assert given[given.index(b"--serve") + 1] == b"47020"  # the model's port tag
    # by the address it serves at, as well as by the model's host name
    assert run(app, env, "stop-host", "127.0.0.2").returncode == 0
    assert run(app, env, "WebLabSide-status").returncode == 3
    started = run(app, env, "start-host", "user.example.org")
    assert started.returncode == 0, started.stderr
    given = Path(env["FAKE_ARGS"]).read_bytes().split(b"\0")
    # it reaches the other host's container at that one's address and port
    assert b"WebLabSide=PYRO:acordcs.container.WebLabSide@127.0.0.2:47020" in given
    assert run(app, env, "UserSide-status").returncode == 0
    assert run(app, env, "WebLabSide-status").returncode == 3


def test_a_missing_or_unknown_host_is_a_usage_error_listing_the_hosts(
    app: Path, env: dict[str, str]
) -> None:
    for args in ((), ("",), ("elsewhere.example.org",)):
        for script in ("start-host", "stop-host"):
            done = run(app, env, script, *args)
            assert done.returncode == 2, done.stderr
            assert (
                "UserSide: user.example.org (setting ACORDCS_UserSide_HOST: user.example.org)"
                in (done.stderr)
            )
            assert (
                "WebLabSide: weblab.example.org (setting ACORDCS_WebLabSide_HOST: 127.0.0.2)"
                in (done.stderr)
            )
    assert "no container runs on host elsewhere.example.org" in done.stderr
    assert not (Path(env["ACORDCS_RUN_DIR"]) / "UserSide.pid").exists()
