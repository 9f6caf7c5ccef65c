"""A fleet on loopback for the tests: certificates from ``lupin fleet certs``, a real router
(zenoh's router mode, mutual TLS, the fleet's access control) on a free port, and sessions that
connect to it under any member's certificate, as a robot, a console or an intruder would."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import zenoh

from fleet.certs import member_files
from fleet.members import read_members
from fleet.router import open_router
from lupin.cli import main
from mission.link.session import free_endpoint, session_config
from tests.link.sim_service import wait_for  # noqa: F401  (the fleet's tests wait the same way)

ROBOTS, CONSOLES = ["r1", "r2", "r3"], ["ops"]


@pytest.fixture(scope="session")
def certs(tmp_path_factory) -> Path:
    """The fleet's certificates, made by the command a user runs."""
    out = tmp_path_factory.mktemp("fleet") / "certs"
    assert main(["fleet", "certs", "--robots", ",".join(ROBOTS), "--consoles", ",".join(CONSOLES), "-o", str(out)]) == 0
    return out


@pytest.fixture
def router(certs):
    """A TLS router with the fleet's access control; yields its endpoint."""
    endpoint = free_endpoint("tls")
    session = open_router(endpoint, member_files(certs, "router"), read_members(certs))
    try:
        yield endpoint
    finally:
        session.close()


def member(endpoint: str, certs: Path, name: str) -> zenoh.Session:
    return zenoh.open(session_config("connect", endpoint, member_files(certs, name)))


def ask(session: zenoh.Session, key: str, payload: dict | None = None, timeout: float = 1.0) -> list:
    """Every answer to a query on ``key``: payload bytes, or ("err", bytes)."""
    out = []
    for r in session.get(key, payload=json.dumps(payload or {}).encode(), timeout=timeout,
                         target=zenoh.QueryTarget.ALL, consolidation=zenoh.ConsolidationMode.NONE):
        out.append(r.ok.payload.to_bytes() if r.ok is not None else ("err", r.err.payload.to_bytes()))
    return out
