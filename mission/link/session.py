"""Opening a Zenoh session for the link: endpoints, modes, TLS files, no multicast scouting.

A robot alone (``lupin serve``) listens as a peer and consoles connect straight to it, as
before the fleet. In a fleet every member connects to the router as a client (spec/fleet.md,
"The router"); over ``tls/`` endpoints each presents its own certificate and checks the
router's against the fleet's authority (mutual TLS: ``TlsFiles``). Multicast scouting is off
everywhere: the link goes where it is told, never to whoever answers on the farm's network.
"""
from __future__ import annotations

import json
import re
import socket
from dataclasses import dataclass
from pathlib import Path

import zenoh

from hw.errors import InputError

ROBOT_LEASE_MS = 800
"""A robot on a router announces this lease: silent this long, the router takes it for dead and its
liveliness token goes, spec/fleet.md's "within a second" for a robot that drops off the network or
hangs, not just one whose process ends (a closed socket is seen at once). zenoh's default is 10 s
(measured: a frozen robot stayed listed 10.0 s; with 1000 ms, 0.99-1.01 s: too close to the
second); the robot sends keep-alives four times a lease (zenoh's ``keep_alive``), a few bytes
each. Consoles keep the default: a console on a busy laptop should not lose its link over a late
keep-alive. A machine stalled longer than the lease drops a live robot's token too (measured at
load 20 on 2 cores: every robot's at once, back within 0.05 s of the stall's end): what must not
believe that at once, the aisle locks, waits out a grace (``mission.link.roster``)."""

ENDPOINT = re.compile(r"^(tcp|udp|tls|quic|ws|unixsock-stream)/\S+$")


@dataclass(frozen=True)
class TlsFiles:
    """One member's TLS files: the fleet authority's certificate, its own certificate and key
    (``fleet.certs.member_files`` finds and checks them)."""

    ca: Path
    cert: Path
    key: Path


def check_endpoint(endpoint: str, option: str) -> str:
    """``proto/address`` as Zenoh spells it, e.g. ``tcp/127.0.0.1:7447``; InputError otherwise."""
    if not ENDPOINT.match(endpoint):
        raise InputError(f"{option} {endpoint}: not a Zenoh endpoint (expected e.g. tcp/127.0.0.1:7447)")
    return endpoint


def free_endpoint(proto: str = "tcp") -> str:
    """A loopback endpoint on a TCP port free right now (a child service, a test, a bench)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return f"{proto}/127.0.0.1:{s.getsockname()[1]}"


def tls_settings(tls: TlsFiles, side: str) -> dict:
    """zenoh's ``transport.link.tls`` for one side (``listen`` or ``connect``): mutual TLS, the
    fleet's authority the only one trusted."""
    return {"root_ca_certificate": str(tls.ca.absolute()), "enable_mtls": True,
            f"{side}_private_key": str(tls.key.absolute()), f"{side}_certificate": str(tls.cert.absolute())}


def session_config(mode: str, endpoint: str, tls: TlsFiles | None = None, *, lease_ms: int | None = None) -> zenoh.Config:
    """An explicit Zenoh config: ``listen`` (a peer) or ``connect`` (a client), no multicast
    scouting; ``tls`` for a ``tls/`` endpoint; ``lease_ms``: the lease it announces."""
    if tls is None and endpoint.startswith("tls/"):
        raise InputError(f"{endpoint}: a tls/ endpoint needs the fleet's certificates (--certs DIR)")
    conf = zenoh.Config()
    conf.insert_json5("mode", json.dumps("peer" if mode == "listen" else "client"))
    conf.insert_json5(f"{mode}/endpoints", json.dumps([endpoint]))
    conf.insert_json5("scouting/multicast/enabled", "false")
    if lease_ms is not None:
        conf.insert_json5("transport/link/tx/lease", str(lease_ms))
    if tls is not None:
        conf.insert_json5("transport/link/tls", json.dumps(tls_settings(tls, mode)))
    return conf


def open_session(conf: zenoh.Config, mode: str, endpoint: str, option: str) -> zenoh.Session:
    """``zenoh.open``, its failure one line naming the option and endpoint (InputError)."""
    try:
        return zenoh.open(conf)
    except zenoh.ZError as exc:
        doing = "cannot listen there" if mode == "listen" else "cannot connect (is the router up, and are the certificates the fleet's?)"
        raise InputError(f"{option} {endpoint}: {doing}: {exc}") from None
