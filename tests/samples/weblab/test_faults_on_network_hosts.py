"""The WebLab on network hosts the test makes (namespaces on a bridge, link-local addresses, torn
down after: tests/support/netns.py), its context through mosquitto on a host of its own
(``ACORDCS_CONTEXT=mqtt://...``), three times at once: one user side and one lab side per access
network of the simulation (residential, campus, LAN), each user's link shaped to the profile's
bandwidth with ``tc tbf`` and given the profile's one-way latency by a relay on each side
(tests/support/latency_relay.py; no netem here: jitter and loss are not emulated). Then faults:

- the cycle rate's ordering that the simulation predicts, residential < campus < LAN, holds on
  the real links, as the Navigator counts it and as the lab's Control monitor measures it, and
  the lab's SpeedLimiting policy sets a lower speed limit on the residential line than on the LAN;
  each lab's telemetry went through the broker (its latest document is retained there, under the
  application's own topic prefix);
- the user's link down for 5 s, watched from the lab's host through the lab container's observer
  interface (tests/support/observer_peer.py): the lab's Control monitor goes stale (no move for
  its 1 s) and measures its cycle rate up to now, falling below "small"; SpeedLimiting fires with
  it and lowers the speed limit to "slow", BandwidthLimiting lowers the camera's frame rate; when
  the link returns Control is fresh, its rate and the rules for a large one are back, in the same
  processes;
- a lab side killed with SIGKILL and started again by its script: the Navigator's calls fail
  meanwhile, it retries, and its run resumes against the new process without a restart;
- a partition healing: a publisher's host cut off from the broker and from the subscriber's host
  until the broker has dropped it, then joined again: it reconnects, and the subscriber (a
  persistent session) is handed every QoS 1 document once (sequence numbers);
- bad input at start inside the namespaces: a broker name that does not resolve (the hosts have
  their own resolv.conf and hosts files: no name reaches a real DNS server), a broker refusing
  the connection, a lab side's own address that does not resolve; each a clear error naming the
  container, host and port, at once.

Needs root (skips outside CI otherwise, fails in CI). Measured: 72 s on a 2-core machine at a load
average of 26, most of it the three runs at once (six containers starting); 14 s the kill, 10 to 19 s the
outage, 7 s the partition, 2 s the bad starts."""

from __future__ import annotations

import functools
import json
import os
import re
import secrets
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from weblab_sim.network import PROFILES

from tests.samples.weblab.conftest import APP_DIR, SAMPLE_DIR
from tests.samples.weblab.test_live_mode_on_three_network_hosts import Output
from tests.support import netns
from tests.support.services import mosquitto_binary, wait_for
from tests.support.toolchain import ROOT

pytestmark = pytest.mark.service

RATES = {"residential": "2mbit", "campus": "10mbit", "LAN": "100mbit"}  # the profiles' bandwidth
SHORT = {"residential": "r", "campus": "c", "LAN": "l"}
PEER_ENV = {**os.environ, "PYTHONPATH": f"{ROOT}:{ROOT / 'src'}"}  # the test's own helpers
USER_PORT, LAB_PORT = 47011, 47020  # the WebLab's containers' ports (the model's numbering)
TIME_CAP = 6  # s each profile's Navigator drives


@pytest.fixture(scope="module")
def network():
    netns.require_namespaces()
    names = [f"{SHORT[p]}-{side}" for p in PROFILES for side in ("user", "lab")]
    made = netns.make_network(*names, "broker", hosts={"ctx.example.org": "broker"})
    yield made
    made.teardown()


@pytest.fixture(scope="module")
def broker(network: netns.Network, tmp_path_factory: pytest.TempPathFactory):
    """mosquitto on the broker's host; yields its log's path."""
    work = tmp_path_factory.mktemp("broker")
    host = network.hosts["broker"]
    conf = netns.broker_config(host, work)
    process = subprocess.Popen(host.command(mosquitto_binary(), "-c", str(conf)),
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    log = work / "mosquitto.log"
    try:
        assert wait_for(lambda: log.exists() and "listen socket" in log.read_text(), 10)
        yield log
    finally:
        process.terminate()
        process.wait(timeout=10)


class Pair:
    """One WebLab deployment: a user machine and a lab machine (a copy of the built directory
    each), the user's link shaped to a profile, a latency relay on each side."""

    def __init__(self, profile: str, network: netns.Network, tmp: Path) -> None:
        self.profile, self.network, self.tmp = profile, network, tmp / profile
        self.user = network.hosts[f"{SHORT[profile]}-user"]
        self.lab = network.hosts[f"{SHORT[profile]}-lab"]
        self.token = secrets.token_hex(16)
        broker = network.hosts["broker"]
        self.context = f"mqtt://{broker.address}:1883/weblab-{SHORT[profile]}"
        self.copies = {}
        for host in (self.user, self.lab):
            self.copies[host.name] = self.tmp / host.name
            shutil.copytree(APP_DIR, self.copies[host.name],
                            ignore=shutil.ignore_patterns("run", "__pycache__"))  # fmt: skip
        self.relays: list[subprocess.Popen] = []
        self.user_log = self.tmp / f"run-{self.user.name}" / "UserSide.log"
        self.lab_log = self.tmp / f"run-{self.lab.name}" / "WebLabSide.log"

    def env(self, host: netns.Host, **extra: str) -> dict[str, str]:
        """The environment of each machine: the containers' addresses as that machine reaches
        them (the other side through its relay on loopback), the context's broker."""
        on_user = host is self.user
        return {
            **{k: v for k, v in os.environ.items() if not k.startswith(("ACORDCS_", "WEBLAB_"))},
            "PYTHON": sys.executable,
            "PYTHONPATH": f"{SAMPLE_DIR}:{ROOT / 'src'}",
            "ACORDCS_RUN_DIR": str(self.tmp / f"run-{host.name}"),
            "ACORDCS_TOKEN": self.token,
            "ACORDCS_CLOCK": "real",
            "ACORDCS_UserSide_HOST": self.user.address if on_user else "127.0.0.1",
            "ACORDCS_WebLabSide_HOST": "127.0.0.1" if on_user else self.lab.address,
            "ACORDCS_UserSide_RUN": "Navigator.run",
            "ACORDCS_TIMEOUT": "2",
            "ACORDCS_STOP_TIMEOUT": "5",
            "WEBLAB_TIME_CAP": str(TIME_CAP),
            "WEBLAB_FORWARD_SPEED": "200",
            # the lab side's context (the telemetry documents) through the broker's host
            **({} if on_user else {"ACORDCS_CONTEXT": self.context}),
            **extra,
        }

    def script(self, host: netns.Host, name: str, *args: str, **extra: str):
        return subprocess.run(host.command("sh", str(self.copies[host.name] / "bin" / name), *args),
                              env=self.env(host, **extra), capture_output=True, text=True,
                              timeout=90)  # fmt: skip

    def link(self) -> None:
        """The user's link shaped to the profile's rate, and its one-way latency each way."""
        self.network.shape(self.user.name, RATES[self.profile])
        delay = str(PROFILES[self.profile].latency)
        relay = [sys.executable, "-m", "tests.support.latency_relay"]
        for host, port, target in (
            (self.user, LAB_PORT, self.lab),
            (self.lab, USER_PORT, self.user),
        ):
            process = subprocess.Popen(
                host.command(*relay, f"127.0.0.1:{port}", f"{target.address}:{port}", delay),
                env=PEER_ENV, stdout=subprocess.PIPE, text=True)  # fmt: skip
            self.relays.append(process)
            assert process.stdout is not None and process.stdout.readline() == "relaying\n"

    def starts(self, **extra: str) -> list:
        """The calls that start the two sides (at once: the Navigator waits for the lab)."""
        return [functools.partial(self.script, self.lab, "start-host", "weblab.example.org", **extra),
                functools.partial(self.script, self.user, "start-host", "user.example.org", **extra)]  # fmt: skip

    def stop(self) -> tuple[int, int]:
        stopped = self.script(self.user, "stop-host", "user.example.org").returncode
        return stopped, self.script(self.lab, "stop-host", "weblab.example.org").returncode

    def said(self, pattern: str, log: Path | None = None) -> re.Match | None:
        path = log or self.user_log
        return re.search(pattern, path.read_text() if path.exists() else "", re.M)

    def close(self) -> None:
        for relay in self.relays:
            relay.kill()
            relay.wait(timeout=10)


def at_once(*calls):
    """Call each in a thread of its own; their results, in order (an exception is raised again)."""
    results: list = [None] * len(calls)

    def run(i: int) -> None:
        try:
            results[i] = calls[i]()
        except BaseException as err:  # handed to the test's thread
            results[i] = err

    threads = [threading.Thread(target=run, args=(i,)) for i in range(len(calls))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=180)
    for result in results:
        if isinstance(result, BaseException):
            raise result
    return results


def retained(network: netns.Network, topic: str) -> str:
    """The document the broker keeps retained on ``topic`` (empty: none within 5 s)."""
    broker = network.hosts["broker"]
    peer = [sys.executable, "-m", "tests.support.context_peer", "retained"]
    got = subprocess.run(broker.command(*peer, broker.address, topic), capture_output=True,
                         text=True, timeout=30, env=PEER_ENV)  # fmt: skip
    return got.stdout


def adapted(pair: Pair) -> tuple[float, float] | None:
    """The lab's last line with a cycle rate measured: (Control's cycleRate, SpeedLimiting's
    maxSpeed); None before the robot has been driven."""
    text = pair.lab_log.read_text() if pair.lab_log.exists() else ""
    found = re.findall(r"^WebLab t=.*Control: cycleRate ([\d.]+)/s.*maxSpeed +([\d.]+) mm/s",
                       text, re.M)  # fmt: skip
    driven = [(float(rate), float(speed)) for rate, speed in found if float(rate) > 0]
    return driven[-1] if driven else None


def cycle_rate(pair: Pair) -> float:
    found = pair.said(
        r"^Navigator: time cap of \d+ s reached: \d+ cycles in [\d.]+ s = ([\d.]+) cycles/s"
    )
    assert found, pair.user_log.read_text()
    return float(found.group(1))


def test_the_cycle_rate_orders_the_profiles_on_real_links_with_context_over_the_broker(
    weblab_app: None, network: netns.Network, broker: Path, tmp_path: Path
) -> None:
    pairs = [Pair(p, network, tmp_path) for p in PROFILES]
    stopped: list = []
    try:
        for pair in pairs:
            pair.link()
        for started in at_once(*(start for pair in pairs for start in pair.starts())):
            assert started.returncode == 0, started.stdout + started.stderr
        for pair in pairs:
            assert wait_for(lambda pair=pair: pair.said(r"^Navigator: time cap"), TIME_CAP + 40), \
                pair.user_log.read_text()  # fmt: skip
        # the lab's own view, every 5 s of its run: what its monitor measured, its policies set
        for pair in pairs:
            assert wait_for(lambda pair=pair: adapted(pair) is not None, 15), (
                f"{pair.profile}: the lab measured no cycle rate\n--- the lab's log:\n"
                + pair.lab_log.read_text()
                + "\n--- the user's log:\n"
                + pair.user_log.read_text()[-6000:]
            )
        adaptation = {pair.profile: adapted(pair) for pair in pairs}
    finally:
        stopped = at_once(*(pair.stop for pair in pairs))
        for pair in pairs:
            pair.close()
    rates = {pair.profile: cycle_rate(pair) for pair in pairs}
    assert rates["residential"] < rates["campus"] < rates["LAN"], rates
    # the lab's Control monitor measures the same order, and SpeedLimiting slows the robot on
    # the slow line (its fuzzy rules: a small cycle rate, a lower speed limit), as in the
    # simulation
    measured = {profile: found[0] for profile, found in adaptation.items()}
    assert measured["residential"] < measured["campus"] < measured["LAN"], adaptation
    assert adaptation["residential"][1] < adaptation["LAN"][1], adaptation
    for pair in pairs:
        assert pair.said(r"^UserSide: stopped at t=[\d.]+ s, faults: 0$"), pair.user_log.read_text()
        # the lab side's pushes to the user (telemetry, panorama) before the user side serves and
        # after it stops fail, as faults of the lab side; its own run goes on
        assert pair.said(r"^WebLabSide: stopped at t=[\d.]+ s, faults: \d+$", pair.lab_log)
        # the lab's telemetry went through the broker: the latest is retained under its prefix
        kept = retained(network, f"weblab-{SHORT[pair.profile]}/Locomotion")
        assert "<telemetry><positionX>" in kept, (pair.profile, kept)
    assert all(s == (0, 0) for s in stopped), stopped
    print("cycles/s on real links:", rates, "the labs' (cycleRate, maxSpeed):", adaptation)


def cycle_lines(pair: Pair) -> list[str]:
    text = pair.user_log.read_text() if pair.user_log.exists() else ""
    return [line for line in text.splitlines() if re.match(r"Navigator t=.*: (cycle|a call)", line)]


def test_a_lab_side_killed_and_started_again_by_its_script_is_driven_on(
    weblab_app: None, network: netns.Network, broker: Path, tmp_path: Path
) -> None:
    pair = Pair("LAN", network, tmp_path)
    lab_pid = pair.tmp / f"run-{pair.lab.name}" / "WebLabSide.pid"
    try:
        pair.link()
        for started in at_once(*pair.starts(WEBLAB_TIME_CAP="60")):
            assert started.returncode == 0, started.stdout + started.stderr
        user_status = pair.script(pair.user, "UserSide-status").stdout
        assert wait_for(lambda: any("cycle" in x for x in cycle_lines(pair)), 30), cycle_lines(pair)
        killed = int(lab_pid.read_text())
        os.kill(killed, signal.SIGKILL)
        assert wait_for(lambda: "a call to the WebLab failed" in "".join(cycle_lines(pair)), 20)
        # its script starts it again: the pid file of the killed process is taken for stale
        again = pair.script(pair.lab, "WebLabSide-start")
        assert again.returncode == 0, again.stdout + again.stderr
        # (the killed one is gone, or a zombie whose command line is empty until it is reaped)
        assert re.search(rf"pid file \S+ not used: (no )?process {killed} .*; not signalled, removed",
                         again.stderr), again.stderr  # fmt: skip
        failed_at = max(i for i, x in enumerate(cycle_lines(pair)) if "failed" in x)
        # the Navigator, the same process, drives on against the new lab side
        assert wait_for(lambda: any("cycle" in x for x in cycle_lines(pair)[failed_at + 1 :]), 30), \
            cycle_lines(pair)  # fmt: skip
        assert pair.script(pair.user, "UserSide-status").stdout == user_status
    finally:
        stopped = pair.stop()
        pair.close()
    assert stopped == (0, 0), stopped
    assert pair.said(r"^UserSide: stopped at t=[\d.]+ s, faults: 0$"), pair.user_log.read_text()
    lab = pair.lab_log.read_text()  # the log of the second process (the first one's is replaced)
    assert "WebLabSide: serving at" in lab and "stopped at t=" in lab, lab


OUTAGE = 5.0  # s the user's link is down


class Observed:
    """The lab container's events as a watcher on the lab's host sees them through its observer
    interface (tests/support/observer_peer.py): Control's readings and staleness, the firings of
    the two policy sets it feeds; each with the wall-clock time it happened at."""

    ELEMENTS = ("Control", "SpeedLimiting", "BandwidthLimiting")

    def __init__(self, pair: Pair) -> None:
        peer = [sys.executable, "-m", "tests.support.observer_peer"]
        self.process = subprocess.Popen(
            pair.lab.command(*peer, pair.lab.address, str(LAB_PORT), "WebLabSide", *self.ELEMENTS),
            env={**PEER_ENV, "ACORDCS_TOKEN": pair.token}, stdout=subprocess.PIPE, text=True)  # fmt: skip
        self.out = Output(self.process)

    def events(self) -> list[dict]:
        with self.out.lock:
            lines = list(self.out.lines)
        return [json.loads(line) for line in lines if line.startswith("{")]

    def rates(self, start: float = 0.0, end: float = float("inf")) -> list[tuple[float, float]]:
        """Control's cycle rates published between the two times: (wall, cycles/s)."""
        return [(e["wall"], e["values"]["cycleRate"]) for e in self.events()
                if e["kind"] == "monitor.updated" and "cycleRate" in e["values"]
                and start <= e["wall"] <= end]  # fmt: skip

    def staleness(self, stale: bool) -> list[dict]:
        return [e for e in self.events() if e["kind"] == "monitor.stale" and e["value"] is stale]

    def firings(self, name: str, start: float = 0.0, end: float = float("inf")) -> list[dict]:
        return [e["firing"] for e in self.events() if e["kind"] == "policy.fired"
                and e["element"] == name and "firing" in e and start <= e["wall"] <= end]  # fmt: skip

    def close(self) -> None:
        self.process.kill()
        self.process.wait(timeout=10)


def rules(firing: dict, rate: str) -> list[str]:
    """The rules of a firing for that linguistic value of the cycle rate (small, large) that
    fired (degree > 0)."""
    return [label for _, label, degree in firing["rules"] if label.startswith(rate) and degree > 0]


def running_pids(pair: Pair) -> dict[str, int]:
    """Each side's pid, from its pid file, checked alive."""
    pids = {}
    for host, side in ((pair.user, "UserSide"), (pair.lab, "WebLabSide")):
        pid = int((pair.tmp / f"run-{host.name}" / f"{side}.pid").read_text())
        os.kill(pid, 0)  # alive (ProcessLookupError otherwise)
        pids[side] = pid
    return pids


def spell(observed: Observed, down: float, up: float) -> tuple[dict, dict] | None:
    """Control's stale spell of the outage: its going stale while the link was down and its being
    fresh again after the link came back, the two events (None: not over yet)."""
    went = [e for e in observed.staleness(True) if down <= e["wall"] <= up]
    back = [e for e in observed.staleness(False) if went and e["seq"] > went[0]["seq"]]
    return (went[0], back[0]) if back else None


def within(events: list[dict], spell: tuple[dict, dict]) -> list[dict]:
    """The events between the two, in the container's order (their numbers)."""
    return [e for e in events if spell[0]["seq"] < e["seq"] < spell[1]["seq"]]


def readings(events: list[dict], name: str) -> list[dict]:
    return [e for e in events if e["kind"] == "monitor.updated" and e["element"] == name]


def fired(events: list[dict], name: str) -> list[dict]:
    return [e["firing"] for e in events if e["kind"] == "policy.fired"
            and e["element"] == name and "firing" in e]  # fmt: skip


def test_during_an_outage_the_labs_monitor_sees_it_and_its_policies_adapt(
    weblab_app: None, network: netns.Network, broker: Path, tmp_path: Path
) -> None:
    pair = Pair("LAN", network, tmp_path)
    observed: Observed | None = None
    try:
        pair.link()
        for started in at_once(*pair.starts(WEBLAB_TIME_CAP="60")):
            assert started.returncode == 0, started.stdout + started.stderr
        pids = running_pids(pair)
        observed = Observed(pair)
        assert wait_for(lambda: observed.out.has("ready"), 20), observed.out.lines
        # driven: the camera's frame rate set from a measured cycle rate (BandwidthLimiting's
        # period is 2 s), and the speed limit from the latest one
        assert wait_for(lambda: any(f["inputs"].get("Control.cycleRate", 0) > 0
                                    for f in observed.firings("BandwidthLimiting")), 20), \
            observed.events()  # fmt: skip
        speed_before = observed.firings("SpeedLimiting")[-1]
        frames_before = observed.firings("BandwidthLimiting")[-1]
        rate_before = observed.rates()[-1][1]
        down = time.time()
        network.link_down(pair.user.name)
        try:
            time.sleep(OUTAGE)  # the fault itself
        finally:
            network.link_up(pair.user.name)
        up = time.time()
        # the link returns: Control is fresh, fed by the Navigator's calls again (its moves and
        # stops: it drives on, the same process)
        assert wait_for(lambda: spell(observed, down, up) is not None, 30), \
            (down, up, observed.staleness(True), pair.user_log.read_text())  # fmt: skip

        def driven_again() -> list[dict]:
            found = spell(observed, down, up)
            assert found is not None
            return [e for e in readings(observed.events(), "Control")
                    if e["seq"] > found[1]["seq"] and "speed" in e["values"]]  # fmt: skip

        # the reading that made it fresh: a call of the Navigator's (more of them may still time
        # out for a while: docs/deployment.md)
        assert wait_for(lambda: driven_again(), 10), \
            pair.user_log.read_text() + pair.lab_log.read_text()[-6000:]  # fmt: skip
        events = observed.events()
        pids_after = running_pids(pair)
        user_status = pair.script(pair.user, "UserSide-status")
        lab_status = pair.script(pair.lab, "WebLabSide-status")
    finally:
        if observed is not None:
            observed.close()
        stopped = pair.stop()
        pair.close()
    outage = spell(observed, down, up)
    assert outage is not None
    went, back = outage
    # (a) the monitor observed the outage: stale after its 1 s without a call (its pushes to
    # the user wait in their outboxes, not on the lab's clock thread), with the silence's own
    # readings meanwhile, a cycle rate falling into "small" (below 1.2/s)
    assert went["data"]["cause"].startswith("no call through Locomotion.LocomotionPort for"), went
    during = [e["values"]["cycleRate"] for e in readings(within(events, outage), "Control")]
    assert during and min(during) < 1.2 and min(during) < 0.5 * rate_before, (rate_before, during)
    assert during == sorted(during, reverse=True), during
    assert all(
        set(e["values"]) == {"cycleRate"} for e in readings(within(events, outage), "Control")
    )
    # (b) the policies adapted meanwhile, fed the outage's rate: SpeedLimiting's rules for a
    # small rate fired and set the speed limit to "slow" (at most 110 mm/s) from what it was;
    # BandwidthLimiting lowered the camera's frame rate
    slow = [f for f in fired(within(events, outage), "SpeedLimiting")
            if f["inputs"]["Control.cycleRate"] < 1.2]  # fmt: skip
    assert slow and rules(slow[-1], "small") and not rules(speed_before, "small"), \
        (speed_before, fired(within(events, outage), "SpeedLimiting"))  # fmt: skip
    limit = slow[-1]["outputs"]["Locomotion.maxSpeed"]
    assert limit <= 110 < speed_before["outputs"]["Locomotion.maxSpeed"], (speed_before, slow)
    lowered = [f for f in fired(within(events, outage), "BandwidthLimiting")
               if f["inputs"]["Control.cycleRate"] < 1.2]  # fmt: skip
    fps = frames_before["outputs"]["PanoramicCamera.fps"]
    assert lowered and lowered[-1]["outputs"]["PanoramicCamera.fps"] < fps, (fps, lowered)
    # (c) the link returned: fresh again after it (how long it was stale: the two events' times),
    # read from the Navigator's calls again, in the same processes, no fault in the user side
    assert down <= went["wall"] <= up < back["wall"], (down, up, outage)
    assert abs(back["data"]["stale_for"] - (back["time"] - went["time"])) < 1e-3, outage
    assert user_status.returncode == 0 and lab_status.returncode == 0
    assert pids_after == pids, (pids, pids_after)
    assert stopped == (0, 0), stopped
    assert pair.said(r"^UserSide: stopped at t=[\d.]+ s, faults: 0$"), pair.user_log.read_text()
    print(f"Control stale from {went['wall'] - down:.2f} s to {back['wall'] - down:.2f} s after "
          f"the link went down (up again at {up - down:.2f} s)")  # fmt: skip
    for e in events:
        if e["wall"] < down - 1 or e["kind"] != "policy.fired":
            continue
        inputs, outputs = e["firing"]["inputs"], e["firing"]["outputs"]
        print(f"{e['wall'] - down:6.2f} s {e['element']}: "
              + ", ".join(f"{k} {v:.3g}" for k, v in {**inputs, **outputs}.items()))  # fmt: skip
    print("\n".join(cycle_lines(pair)))


def test_a_partition_heals_and_qos1_documents_arrive_each_once(
    network: netns.Network, broker: Path
) -> None:
    publisher_host, subscriber_host = network.hosts["c-user"], network.hosts["c-lab"]
    address = network.hosts["broker"].address
    peer = [sys.executable, "-m", "tests.support.context_peer"]
    processes: list[subprocess.Popen] = []

    def start(host: netns.Host, *argv: str) -> tuple[subprocess.Popen, Output]:
        process = subprocess.Popen(host.command(*peer, *argv), env=PEER_ENV, text=True,
                                   stdout=subprocess.PIPE)  # fmt: skip
        processes.append(process)
        return process, Output(process)

    def dropped() -> bool:  # the broker's log: it gave up the publisher's connection
        return "Client context-peer-publisher has exceeded timeout" in broker.read_text()

    try:
        subscriber, sub_out = start(subscriber_host, "subscribe", address)
        assert wait_for(lambda: sub_out.has("ready"), 20), sub_out.lines
        publisher, pub_out = start(publisher_host, "publish", address, "600", "100", "1")
        assert wait_for(lambda: pub_out.has("published 100"), 20), pub_out.lines
        network.link_down(publisher_host.name)  # cut off from the broker and the other host
        try:
            assert wait_for(dropped, 20)
        finally:
            network.link_up(publisher_host.name)
        publisher.wait(timeout=60)
        pub_out.reader.join(5)
        subscriber.wait(timeout=60)
        sub_out.reader.join(5)
    finally:
        for process in processes:
            if process.poll() is None:
                process.kill()
                process.wait(timeout=10)
    published = json.loads(pub_out.lines[-1])
    assert published["unacknowledged"] == 0 and published["reconnects"] >= 1, published
    figures = json.loads(sub_out.lines[-1])
    seqs = figures.pop("seqs")
    assert sorted(seqs) == list(range(1, 601)), (sorted(set(range(1, 601)) - set(seqs)), figures)
    assert figures["lost"] == 0, figures


BAD_STARTS = [  # a setting of the lab side, and what its start says
    ({"ACORDCS_CONTEXT": "mqtt://ctx.invalid"},
     "container 'WebLabSide': error: its context broker mqtt://ctx.invalid:1883: the host name "
     "'ctx.invalid' does not resolve"),
    ({"ACORDCS_CONTEXT": "mqtt://ctx.example.org:1884"},  # the broker's host, no broker there
     "container 'WebLabSide': error: its context broker mqtt://ctx.example.org:1884: cannot "
     "reach the MQTT broker at ctx.example.org:1884: [Errno 111] Connection refused"),
    ({"ACORDCS_WebLabSide_HOST": "lab.invalid"},
     "container 'WebLabSide' cannot serve at lab.invalid:47020:"),
]  # fmt: skip


def test_a_bad_address_at_start_is_said_at_once(
    weblab_app: None, network: netns.Network, broker: Path, tmp_path: Path
) -> None:
    pairs = [Pair("residential", network, tmp_path / str(i)) for i in range(len(BAD_STARTS))]
    starts = at_once(*(
        functools.partial(pair.script, pair.lab, "start-host", "weblab.example.org",
                          ACORDCS_START_TIMEOUT="10", **setting)
        for pair, (setting, _) in zip(pairs, BAD_STARTS, strict=True)
    ))  # fmt: skip
    for started, (_, said) in zip(starts, BAD_STARTS, strict=True):
        out = started.stdout + started.stderr
        assert started.returncode == 1, out
        assert "WebLabSide: stopped before serving" in out and said in out, out
