"""A sample application built, started by its generated scripts (loopback, the run directory
and ports of a temporary directory, the application's token), and the console of
``acordcs-gen console`` attached to it in this process, served on uvicorn in a thread: what the
console's tests share, one started application per test module."""

from __future__ import annotations

import contextlib
import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from acordcs.console.fanout import ConsoleHub
from acordcs.console.in_thread import serving
from acordcs.console.live_session import LiveSession
from acordcs.console.site_guard import allowed_names
from acordcs.console.web_app import console_refusals, create_app
from acordcs.descriptor import Application, from_xml
from acordcs.runtime.refusals import Refusals
from tests.generator.test_shell_scripts_parse_quote_and_run import free_ports
from tests.samples.test_every_sample_builds_and_runs import sample_code, started
from tests.support.generator import build
from tests.support.scripts import environment

TOKEN = "console-test-token"
"""The console's token in the tests (the link's fragment)."""


@dataclass
class Attached:
    """The application (``out``: its directory, ``descriptor``, ``env``: its scripts'
    environment, ``model``: a copy of its model file the console updates from) and the console
    (``url``, ``session``, ``refusals``)."""

    out: Path
    descriptor: Application
    env: dict[str, str]
    model: Path
    url: str
    session: LiveSession
    refusals: Refusals


@contextlib.contextmanager
def attached(model: Path, package: str, tmp: Path, **settings: str) -> Iterator[Attached]:
    """``model`` (its package ``package``) built into ``tmp``, started, and the console on it."""
    out = tmp / "out"
    sample_code(model, package, out)
    copy = tmp / model.name
    shutil.copyfile(model, copy)
    for profile in model.parent.glob("*.profile.uml"):
        shutil.copyfile(profile, tmp / profile.name)
    done = build(copy, out, "-t", "python", "-t", "shell")
    assert done.code == 0, done.both
    descriptor = from_xml((out / package / "descriptor.xml").read_bytes())
    names = [c.name for c in descriptor.containers]
    run_dir = tmp / "run"
    run_dir.mkdir(mode=0o700)
    env = environment(run_dir, ACORDCS_STOP_TIMEOUT="10", **settings)
    for container, port in zip(names, free_ports(len(names)), strict=True):
        env[f"ACORDCS_{container}_HOST"] = "127.0.0.1"
        env[f"ACORDCS_{container}_PORT"] = str(port)
    with started(out / "bin", env, run_dir, names), pytest.MonkeyPatch.context() as patch:
        for key, value in env.items():  # the console finds the application as update does
            if key.startswith("ACORDCS_"):
                patch.setenv(key, value)
        hub = ConsoleHub(max_viewers=4, max_watchers=0)  # started with a token: holders only
        session = LiveSession.attached(hub, TOKEN, out, model=copy, timeout=5.0)
        try:
            session.attach()
            site = session.site()
            refusals = console_refusals(site)
            app = create_app(site, hub, session, allowed_hosts=allowed_names("127.0.0.1"),
                             refusals=refusals)  # fmt: skip
            with serving(app, refusals) as url:
                yield Attached(out, descriptor, env, copy, url, session, refusals)
        finally:
            session.close()
