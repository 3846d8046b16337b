"""Several "hosts" on one machine: Linux network namespaces joined by a bridge (root only).

``NetnsFleet`` makes one namespace for the world (and the runner and recorder), ``agents``
namespaces for the agents and one for the switch: a Linux bridge with a veth pair to every host
namespace. Every host gets ``eth0`` with an address of a private /24 that exists only inside
these namespaces, loopback up and a multicast route (DDS discovery with
``ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET``). Nothing is added to the machine's own namespace: the
veth pairs are created directly inside the namespaces. :meth:`NetnsFleet.close` deletes every
namespace (and so every veth and the bridge in it); it runs on exit of the context manager,
also when the test fails.

Faults on the links, all with nftables inside one host namespace:

- :meth:`loss`: drop a share of the UDP datagrams arriving on ``eth0`` at random
  (``numgen random mod 100 < P``), with a counter to read back how many were dropped;
- :meth:`partition`: drop everything between one host and the other agent hosts, both ways (a
  real network partition between vehicles; the world stands for the vehicle's own autopilot
  link, which is on board and stays up).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

SUBNET = "10.231.7"  # /24 inside the test's namespaces only


def _run(*argv: str, check: bool = True, input: str | None = None) -> subprocess.CompletedProcess:
    p = subprocess.run(list(argv), capture_output=True, text=True, input=input, timeout=30, check=False)
    if check and p.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed ({p.returncode}): {p.stderr.strip()}")
    return p


def unavailable() -> str | None:
    """Why namespaces cannot be used here (None when they can)."""
    if os.geteuid() != 0:
        return "needs root (ip netns, veth, bridge)"
    for tool in ("ip", "nft"):
        if shutil.which(tool) is None:
            return f"'{tool}' not found (scripts/bootstrap installs nftables as root)"
    return None


class NetnsFleet:
    """World host ``w``, agent hosts ``a0..a{n-1}``, switch ``sw``; names carry ``tag``."""

    def __init__(self, tag: str, agents: int = 3) -> None:
        if not re.fullmatch(r"[a-z0-9]{1,6}", tag):
            raise ValueError(f"tag must be 1-6 lowercase letters/digits, got {tag!r}")
        self.tag = tag
        self.world = f"fu{tag}w"
        self.agents = [f"fu{tag}a{i}" for i in range(agents)]
        self.switch = f"fu{tag}sw"
        self.hosts = [self.world, *self.agents]
        self.addr = {h: f"{SUBNET}.{i + 1}" for i, h in enumerate(self.hosts)}
        self._port = {h: f"p{tag}{i}" for i, h in enumerate(self.hosts)}  # bridge side of each veth
        self._made: list[str] = []

    # -- lifetime -------------------------------------------------------------------------
    def __enter__(self) -> NetnsFleet:
        try:
            self._up()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _up(self) -> None:
        for ns in [self.switch, *self.hosts]:
            _run("ip", "netns", "add", ns)
            self._made.append(ns)
            _run("ip", "-n", ns, "link", "set", "lo", "up")
        sw = self.switch
        _run("ip", "-n", sw, "link", "add", "br0", "type", "bridge", "mcast_snooping", "0")
        _run("ip", "-n", sw, "link", "set", "br0", "up")
        for h in self.hosts:
            port = self._port[h]
            # both ends born inside namespaces: nothing appears in the machine's own namespace
            _run("ip", "-n", sw, "link", "add", port, "type", "veth", "peer", "name", "eth0", "netns", h)
            _run("ip", "-n", sw, "link", "set", port, "master", "br0")
            _run("ip", "-n", sw, "link", "set", port, "up")
            _run("ip", "-n", h, "addr", "add", f"{self.addr[h]}/24", "dev", "eth0")
            _run("ip", "-n", h, "link", "set", "eth0", "up")
            _run("ip", "-n", h, "route", "add", "224.0.0.0/4", "dev", "eth0")

    def close(self) -> None:
        for ns in reversed(self._made):
            _run("ip", "netns", "del", ns, check=False)
        self._made.clear()

    def exists(self) -> list[str]:
        """Which of this fleet's namespaces exist now (for the teardown check)."""
        listed = _run("ip", "netns", "list").stdout.split()
        return [ns for ns in [self.switch, *self.hosts] if ns in listed]

    # -- faults ---------------------------------------------------------------------------
    def _nft(self, ns: str, ruleset: str) -> None:
        _run("ip", "netns", "exec", ns, "nft", "-f", "-", input=ruleset)

    def loss(self, ns: str, percent: int) -> None:
        """Drop ``percent`` % of the UDP datagrams that arrive on ``ns``'s eth0, at random."""
        if not 0 <= percent <= 100:
            raise ValueError(f"loss percent must be in 0..100, got {percent}")
        self._nft(
            ns,
            "table inet fuloss {\n chain input {\n  type filter hook input priority 0; policy accept;\n"
            f'  iifname "eth0" meta l4proto udp numgen random mod 100 < {percent} counter drop\n'
            "  }\n}\n",
        )

    def dropped(self, ns: str, table: str = "fuloss") -> int:
        """Packets the table's counters dropped in ``ns`` so far."""
        out = _run("ip", "netns", "exec", ns, "nft", "list", "table", "inet", table).stdout
        return sum(int(m) for m in re.findall(r"counter packets (\d+)", out))

    def partition(self, ns: str) -> None:
        """Cut ``ns`` off from every other agent host, both directions (the world link stays)."""
        peers = ", ".join(self.addr[a] for a in self.agents if a != ns)
        self._nft(
            ns,
            "table inet fucut {\n"
            f"  chain input {{ type filter hook input priority 0; ip saddr {{ {peers} }} counter drop; }}\n"
            f"  chain output {{ type filter hook output priority 0; ip daddr {{ {peers} }} counter drop; }}\n"
            "}\n",
        )

    def heal(self, ns: str) -> None:
        _run("ip", "netns", "exec", ns, "nft", "delete", "table", "inet", "fucut")


def fastdds_profile(path: Path, lease_s: int = 4) -> Path:
    """A Fast DDS profile for the namespaces: UDPv4 only (shared memory would bypass the links:
    all namespaces share /dev/shm), a short lease (a cut-off participant leaves the graph) and
    a 100 ms reliable heartbeat (a datagram lost on a link is repaired in ~0.1 s, not 3 s)."""
    path.write_text(
        f"""<?xml version="1.0" encoding="UTF-8" ?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <transport_descriptors>
    <transport_descriptor><transport_id>udp</transport_id><type>UDPv4</type></transport_descriptor>
  </transport_descriptors>
  <participant profile_name="netns_fleet" is_default_profile="true">
    <rtps>
      <userTransports><transport_id>udp</transport_id></userTransports>
      <useBuiltinTransports>false</useBuiltinTransports>
      <builtin>
        <discovery_config>
          <leaseDuration><sec>{lease_s}</sec></leaseDuration>
          <leaseAnnouncement><sec>0</sec><nanosec>250000000</nanosec></leaseAnnouncement>
          <initialAnnouncements><count>20</count><period><nanosec>100000000</nanosec></period></initialAnnouncements>
        </discovery_config>
      </builtin>
    </rtps>
  </participant>
  <data_writer profile_name="netns_writer" is_default_profile="true">
    <times>
      <heartbeatPeriod><sec>0</sec><nanosec>100000000</nanosec></heartbeatPeriod>
    </times>
  </data_writer>
</profiles>
"""
    )
    return path
