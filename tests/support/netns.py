"""Network hosts for tests: Linux network namespaces the test makes itself, one per host, each
joined by a veth pair to a bridge in a namespace of its own, with link-local addresses
(169.254.0.0/16) that exist only inside them; nothing is configured in the machine's own network
namespace, and nothing is sent to any other address. Everything is torn down at the end (the
fixture's finalizer, also after a failure); namespaces left by a crashed run (their names carry
the pid of the process that made them, which is gone) are removed first.

No name is looked up in a real DNS: each host has its own ``resolv.conf`` (a name server on its
own loopback, where none listens: a name that is not in its ``hosts`` fails at once) and its own
``hosts`` naming the hosts as the test says (``ip netns exec`` mounts ``/etc/netns/<namespace>/``
over ``/etc``; removed at the end).

Needs root and iproute2 (``ip``, ``tc``; Debian package ``iproute2``). Outside CI a machine that
refuses to make namespaces skips with the reason; in CI it fails. Links are shaped with ``tc tbf``
(a rate); the kernel's delay emulation (``netem``) is not available on these machines: latency is
added by a relay (:mod:`tests.support.latency_relay`) where a test needs it."""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import pytest

PREFIX = "acx-"  # every namespace these tests make: acx-<pid>-<n>-<role>
SUBNET = "169.254.33"
ETC_NETNS = Path("/etc/netns")  # where ip netns exec finds a namespace's own resolv.conf, hosts


def ip(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    return subprocess.run(["ip", *args], capture_output=True, text=True, check=check, timeout=30)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def clean_stale() -> list[str]:
    """Delete the namespaces of runs whose process is gone; returns their names."""
    listed = ip("netns", "list", check=False).stdout.split("\n")
    removed = []
    for line in listed:
        name = line.split(" ")[0]
        if not name.startswith(PREFIX):
            continue
        pid = name[len(PREFIX) :].split("-")[0]
        if pid.isdigit() and not _alive(int(pid)):
            kill_processes_in(name)
            ip("netns", "del", name, check=False)
            shutil.rmtree(ETC_NETNS / name, ignore_errors=True)
            removed.append(name)
    return removed


def kill_processes_in(namespace: str) -> None:
    """SIGKILL the processes still running in ``namespace`` (only ours are there)."""
    pids = ip("netns", "pids", namespace, check=False).stdout.split()
    for pid in pids:
        with contextlib.suppress(ProcessLookupError, ValueError):
            os.kill(int(pid), signal.SIGKILL)


def require_namespaces() -> None:
    """Skip (outside CI) or fail (in CI) unless this process can make network namespaces."""
    reason = None
    if shutil.which("ip") is None or shutil.which("tc") is None:
        reason = "iproute2 (ip, tc) is not installed (Debian package iproute2)"
    elif os.geteuid() != 0:
        reason = "network namespaces need root (the test makes its own hosts with ip netns)"
    else:
        probe = f"{PREFIX}{os.getpid()}-probe"
        made = ip("netns", "add", probe, check=False)
        ip("netns", "del", probe, check=False)
        if made.returncode != 0:
            reason = f"this machine refuses to make a network namespace: {made.stderr.strip()}"
    if reason is None:
        return
    if os.environ.get("CI") == "true":
        pytest.fail(f"the network namespace tests must run in CI: {reason}")
    pytest.skip(reason)


@dataclass
class Host:
    """One network host: its namespace, its address, and its link (``eth0`` here, its peer on
    the bridge side)."""

    name: str
    namespace: str
    address: str
    peer: str  # the veth end on the bridge, in the bridge's namespace

    def command(self, *argv: str) -> list[str]:
        """``argv`` run inside this host's namespace."""
        return ["ip", "netns", "exec", self.namespace, *argv]


@dataclass
class Network:
    """Hosts on one bridge. ``shape``, ``link_down``, ``link_up`` act on a host's link."""

    bridge: str  # the bridge's namespace
    hosts: dict[str, Host] = field(default_factory=dict)

    def shape(self, host: str, rate: str) -> None:
        """Limit the host's link to ``rate`` (tc's units: 1mbit, 256kbit) both ways."""
        h = self.hosts[host]
        for where in (["-n", h.namespace, "qdisc", "replace", "dev", "eth0"],
                      ["-n", self.bridge, "qdisc", "replace", "dev", h.peer]):  # fmt: skip
            subprocess.run(["tc", *where, "root", "tbf", "rate", rate, "burst", "16kb",
                            "latency", "200ms"], check=True, capture_output=True)  # fmt: skip

    def link_down(self, host: str) -> None:
        ip("-n", self.bridge, "link", "set", self.hosts[host].peer, "down")

    def link_up(self, host: str) -> None:
        ip("-n", self.bridge, "link", "set", self.hosts[host].peer, "up")

    def teardown(self) -> None:
        namespaces = [h.namespace for h in self.hosts.values()] + [self.bridge]
        for ns in namespaces:
            kill_processes_in(ns)
        for ns in namespaces:
            ip("netns", "del", ns, check=False)
            shutil.rmtree(ETC_NETNS / ns, ignore_errors=True)
        with contextlib.suppress(OSError):  # /etc/netns itself, once no namespace has files there
            ETC_NETNS.rmdir()


_runs = iter(range(1, 1 << 30))


def _own_names(namespace: str, names: dict[str, str]) -> None:
    """The namespace's resolv.conf (no name server reachable) and hosts (``names``: name ->
    address, and localhost)."""
    etc = ETC_NETNS / namespace
    etc.mkdir(parents=True, exist_ok=True)
    (etc / "resolv.conf").write_text("nameserver 127.0.0.1\noptions timeout:1 attempts:1\n")
    lines = ["127.0.0.1 localhost"] + [f"{a} {n}" for n, a in sorted(names.items())]
    (etc / "hosts").write_text("\n".join(lines) + "\n")


def make_network(*names: str, hosts: dict[str, str] | None = None) -> Network:
    """A bridge and one host per name, addresses 169.254.33.1, .2, ... in the order given; each
    host resolves exactly the names ``hosts`` gives (name -> the name of the host it is, e.g.
    ``{"weblab.example.org": "lab"}``), and localhost."""
    clean_stale()
    run = f"{PREFIX}{os.getpid()}-{next(_runs)}-"
    network = Network(bridge=run + "br")
    try:
        ip("netns", "add", network.bridge)
        ip("-n", network.bridge, "link", "add", "br0", "type", "bridge")
        ip("-n", network.bridge, "link", "set", "br0", "up")
        for n, name in enumerate(names, start=1):
            host = Host(name, run + name, f"{SUBNET}.{n}", f"v{n}")
            network.hosts[name] = host
            _own_names(host.namespace, {})
            ip("netns", "add", host.namespace)
            ip("-n", host.namespace, "link", "set", "lo", "up")
            ip("-n", network.bridge, "link", "add", host.peer, "type", "veth", "peer", "name",
               "eth0", "netns", host.namespace)  # fmt: skip
            ip("-n", network.bridge, "link", "set", host.peer, "master", "br0", "up")
            ip("-n", host.namespace, "addr", "add", f"{host.address}/24", "dev", "eth0")
            ip("-n", host.namespace, "link", "set", "eth0", "up")
        addresses = {n: network.hosts[h].address for n, h in (hosts or {}).items()}
        for host in network.hosts.values():
            _own_names(host.namespace, addresses)
    except BaseException:
        network.teardown()
        raise
    return network


BROKER_CONF = """\
listener 1883 {address}
allow_anonymous true
set_tcp_nodelay true
max_queued_messages 100000
user root
persistence true
persistence_location {dir}/
log_dest file {dir}/mosquitto.log
log_type all
"""


def broker_config(host: Host, directory: Path) -> Path:
    """A mosquitto configuration for a broker on ``host``: anonymous, persistent (its state and
    its log, every kind of line, in ``directory``), listening on the host's address only."""
    conf = directory / "mosquitto.conf"
    conf.write_text(BROKER_CONF.format(address=host.address, dir=directory), encoding="utf-8")
    return conf
