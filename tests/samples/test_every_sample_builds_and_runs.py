"""Every model shipped under ``samples/`` works end to end: it validates with no error, builds with
every target, its Python application started by its generated scripts (``bin/start-all``, the run
directory and the ports in a temporary directory, every container on loopback) shows a behaviour of
its own (a policy set of the model changes a property from its default: seen through each
container's observer interface, ``acordcs.observe.<container>``), stops by ``bin/stop-all`` with no
fault recorded, its scripts pass shellcheck and its Java compiles with javac.

Which models: every ``.xmi`` and ``.uml`` file directly in a folder of ``samples/`` (a folder
added later is found too), except ``*.profile.uml`` (a profile, not a model) and the folder
``samples/mistakes/``, whose models are wrong on purpose (the documentation validates them to show
the diagnostics).

A sample's own code: the user classes it ships in ``samples/<folder>/app/<package>/components/``
and ``monitors/`` (as the WebLab does, ``samples/weblab/app``), and the Java classes of its
``language=java`` components in ``samples/<folder>/app/java/`` (``samples/mixed``), are put in the output directory
before the build, which keeps them. A sample whose generic components would do nothing ships the
smallest code that lets its policies act: the tutorial's simulated sensor (``samples/tutorial``),
the thermostat's simulated room (``samples/papyrus``). The settings a sample runs with are its
own way of running, stated in :data:`RUNS` (the WebLab's are those of ``samples/weblab/live.sh``,
with a time cap of 3 s); a sample not listed there runs with none, and any of its policy sets
changing any property is its behaviour.

Needs javac and shellcheck (``make test`` installs them): outside CI (``CI`` is not ``true``)
the test skips without them, after everything else has run; in CI it fails.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import signal
import subprocess
import time
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

from acordcs.descriptor import Application
from acordcs.generator.describe import describe
from acordcs.generator.targets.python import package_name
from acordcs.model.reading import read_model
from tests.generator.test_shell_scripts_parse_quote_and_run import free_ports
from tests.support.generator import build
from tests.support.scripts import alive, environment, script, wait_until
from tests.support.toolchain import SAMPLES, run_main

pytestmark = pytest.mark.service

WRONG_ON_PURPOSE = ("mistakes",)
"""Folders of ``samples/`` whose models are wrong on purpose: not built."""

OBSERVE_SECONDS = 30.0
"""How long a sample has to show its behaviour once its containers serve."""


@dataclass(frozen=True)
class Run:
    """How a sample runs and what it shows: in container ``container``, policy set ``policy_set``
    sets ``output`` (``Element.property``) to a value other than the model's default (None: any
    container, set or property). ``settings``: the environment of its own way of running;
    ``python_path``: the folders of modules its code imports; ``finished``: (container, text) a
    line of that container's log has once its run is over, waited for before stopping."""

    container: str | None = None
    policy_set: str | None = None
    output: str | None = None
    settings: Mapping[str, str] = field(default_factory=dict)
    python_path: tuple[Path, ...] = ()
    finished: tuple[str, str] | None = None


RUNS = {
    # live.sh's settings: the user's Navigator drives the simulated robot over Pyro5 (for 3 s),
    # the Control monitor turns its moves into the SpeedLimiting policy's inputs.
    "weblab/weblab.xmi": Run(
        "WebLabSide",
        "SpeedLimiting",
        "Locomotion.maxSpeed",
        settings={
            "ACORDCS_UserSide_RUN": "Navigator.run",
            "ACORDCS_TIMEOUT": "30",
            "WEBLAB_TIME_CAP": "3",
            "WEBLAB_FORWARD_SPEED": "200",
        },
        python_path=(SAMPLES / "weblab",),
        finished=("UserSide", "--run Navigator.run() returned"),
    ),
    # The tutorial's sensor warms the greenhouse by 1.5 °C a second; Ventilation opens the vent.
    "tutorial/greenhouse.uml": Run("House", "Ventilation", "Vent.opening"),
    # Lighting fires every 5 s on the room's presence and daylight (their defaults: an empty,
    # dark room) and dims the lights; nothing of the sample's own is needed.
    "smartroom/smartroom.xmi": Run("Room", "Lighting", "Lights.dimmer"),
    # The thermostat's room cools by 1 °C a second; Comfort turns the heater up.
    "papyrus/thermostat.uml": Run("Home", "Comfort", "Heater.power"),
    # The ventilation's office gets stale by 100 ppm of CO2 a second; Airflow speeds the fan up.
    "papyrus/ventilation.uml": Run("Plant", "Airflow", "Fan.speed"),
    # The greenhouse with its vent in Java: Ventilation opens the Java component's vent.
    "mixed/greenhouse.uml": Run("House", "Ventilation", "Vent.opening"),
}


def models() -> list[Path]:
    found = []
    for folder in sorted(p for p in SAMPLES.iterdir() if p.is_dir()):
        if folder.name in WRONG_ON_PURPOSE:
            continue
        found += sorted(
            p
            for p in folder.iterdir()
            if p.is_file() and p.suffix in (".xmi", ".uml") and not p.name.endswith(".profile.uml")
        )
    return found


def key(model: Path) -> str:
    return model.relative_to(SAMPLES).as_posix()


def test_the_samples_are_found():
    found = [key(m) for m in models()]
    assert set(RUNS) <= set(found), found  # the samples named here are all found
    assert not [k for k in found if k.startswith("mistakes/") or ".profile." in k]


def sample_code(model: Path, package: str, out: Path) -> list[str]:
    """The user classes the sample ships, copied into ``out`` (where the build keeps them)."""
    copied = []
    for kind in ("components", "monitors"):
        for source in sorted((model.parent / "app" / package / kind).glob("*.py")):
            target = out / package / kind / source.name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(source, target)
            copied.append(f"{package}/{kind}/{source.name}")
    java = model.parent / "app"  # the Java user classes of language=java components
    for source in sorted((java / "java").rglob("*.java")):
        target = out / source.relative_to(java)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
        copied.append(source.relative_to(java).as_posix())
    return copied


def tool(name: str, package: str, missing: list[str]) -> str | None:
    """``name``'s path, or None (said in ``missing``): in CI a missing tool fails the test."""
    found = shutil.which(name)
    if found is None:
        reason = f"{name} is not on PATH (install {package})"
        if os.environ.get("CI") == "true":
            pytest.fail(f"the samples test cannot run {name} in CI: {reason}")
        missing.append(reason)
    return found


# --------------------------------------------------------------------------- the running part
def default_of(app: Application, output: str) -> object:
    element, _, prop = output.partition(".")
    for comp in app.components:
        if comp.name == element:
            return next((p.default for p in comp.properties if p.name == prop), None)
    return None


def changed(app: Application, run: Run, name: str, firing: dict[str, Any] | None) -> list[str]:
    """What a firing of policy set ``name`` set that ``run`` looks for, away from the model's
    default: ``Set: Element.property default -> value``."""
    if firing is None or run.policy_set not in (None, name):
        return []
    out = []
    for output, value in firing.get("outputs", {}).items():
        default = default_of(app, output)
        if run.output in (None, output) and value != default:
            out.append(f"{name}: {output} {default!r} -> {value!r}")
    return out


def observed(app: Application, run: Run, ports: dict[str, int], token: str) -> list[str]:
    """Watches each container ``run`` names (all, if none) until a policy set changes what it
    looks for, or :data:`OBSERVE_SECONDS` pass; what was seen."""
    from acordcs.runtime.connectors.remote import RemoteConnector
    from acordcs.runtime.live.observer import OBSERVE_OBJECT

    names = [run.container] if run.container else list(ports)
    connector = RemoteConnector(timeout=10, token=token)
    seen: list[str] = []
    faults: list[str] = []
    try:
        uris = {n: f"PYRO:{OBSERVE_OBJECT.format(n)}@127.0.0.1:{ports[n]}" for n in names}
        watches = {}
        for name, uri in uris.items():
            reply = connector.request(uri, "watch", [], False, where=f"the observer of {name}")
            watches[name] = [reply["watch"], reply["after"]]
            for set_name, firing in reply["snapshot"]["policy_sets"].items():
                seen += changed(app, run, set_name, firing)
        deadline = time.monotonic() + OBSERVE_SECONDS
        while not seen and not faults and time.monotonic() < deadline:
            for name, uri in uris.items():
                watch, after = watches[name]
                reply = connector.request(uri, "poll", watch, after, 0.5, where=name)
                watches[name][1] = reply["after"]
                faults += [f"{name}: {f['where']}: {f['error']}" for f in reply["faults"]]
                for event in reply["events"]:
                    if event["kind"] == "policy.fired":
                        seen += changed(app, run, event["element"], event.get("firing"))
        for name, uri in uris.items():
            with contextlib.suppress(Exception):
                connector.request(uri, "unwatch", watches[name][0], where=name)
    finally:
        connector.close()
    assert not faults, faults
    return seen


@contextlib.contextmanager
def started(bin_: Path, env: dict[str, str], run_dir: Path, names: list[str]) -> Iterator[None]:
    """``bin/start-all``, and whatever happens ``bin/stop-all`` then a KILL of any container
    process left (a failed test leaves nothing running)."""
    try:
        done = script(bin_, "start-all", env, timeout=120)
        assert done.returncode == 0, done.stdout + done.stderr
        yield
    finally:
        script(bin_, "stop-all", env, timeout=120)
        for name in names:
            pidfile = run_dir / f"{name}.pid"
            pid = int(pidfile.read_text().strip() or 0) if pidfile.exists() else 0
            if pid and alive(pid):
                os.kill(pid, signal.SIGKILL)


@pytest.mark.parametrize("model", models(), ids=key)
def test_the_sample_validates_builds_runs_and_compiles(model: Path, tmp_path: Path):
    run = RUNS.get(key(model), Run())
    missing: list[str] = []
    shellcheck = tool("shellcheck", "shellcheck", missing)
    javac = tool("javac", "openjdk-17-jdk-headless", missing)

    # 1. It validates with no error.
    checked = run_main(["validate", str(model)])
    assert checked.code == 0 and " 0 errors," in checked.out, checked.both

    # 2. It builds with every target, around the code it ships.
    app = describe(read_model(model).architecture)
    package, out = package_name(app.name), tmp_path / "out"
    shipped = sample_code(model, package, out)
    built = build(model, out)
    assert built.code == 0, built.both
    assert all((out / f).read_bytes() == (model.parent / "app" / f).read_bytes()
               for f in shipped)  # fmt: skip

    # 3. Its scripts start it, it shows its behaviour, its scripts stop it, with no fault.
    names = [c.name for c in app.containers]
    run_dir = tmp_path / "run"
    run_dir.mkdir(mode=0o700)
    ports = dict(zip(names, free_ports(len(names)), strict=True))
    env = environment(run_dir, ACORDCS_STOP_TIMEOUT="10", **run.settings)
    for container, port in ports.items():
        env[f"ACORDCS_{container}_HOST"] = "127.0.0.1"
        env[f"ACORDCS_{container}_PORT"] = str(port)
    if run.python_path:
        env["PYTHONPATH"] = os.pathsep.join([*map(str, run.python_path), env.get("PYTHONPATH", "")])
    bin_ = out / "bin"
    with started(bin_, env, run_dir, names):
        token = (run_dir / "token").read_text(encoding="utf-8").strip()
        seen = observed(app, run, ports, token)
        wanted = f"{run.policy_set or 'a policy set'} changing {run.output or 'a property'}"
        assert seen, f"{key(model)}: no {wanted} in {OBSERVE_SECONDS:g} s"
        if run.finished:
            where, line = run.finished
            log = run_dir / f"{where}.log"
            wait_until(lambda: line in log.read_text(encoding="utf-8"), f"{line} in {log}", 60)
        stopped = script(bin_, "stop-all", env, timeout=120)
    assert stopped.returncode == 0, stopped.stdout + stopped.stderr
    for container in names:
        log = (run_dir / f"{container}.log").read_text(encoding="utf-8")
        assert re.search(rf"^{container}: stopped at t=[\d.]+ s, faults: 0$", log, re.M), log

    # 4. Its scripts pass shellcheck.
    if shellcheck:
        scripts = sorted(p.name for p in bin_.iterdir())
        done = subprocess.run([shellcheck, "-s", "sh", "-x", *scripts], cwd=bin_,
                              capture_output=True, text=True, timeout=120)  # fmt: skip
        assert done.returncode == 0, done.stdout + done.stderr

    # 5. Its Java compiles.
    if javac:
        sources = sorted(str(p) for p in (out / "java").rglob("*.java"))
        assert sources
        done = subprocess.run(
            [javac, "-Xlint:all", "-encoding", "US-ASCII", "-d", str(tmp_path / "classes"),
             *sources], capture_output=True, text=True, timeout=300,
        )  # fmt: skip
        assert done.returncode == 0, done.stdout + done.stderr
    if missing:
        pytest.skip(f"validated, built and ran; not checked: {'; '.join(missing)}")
