"""Shared builders for the history tests: a hand-built history (patrols and their rows, as a
test says), and a real PostgreSQL 15 server on loopback.

The server (``lupin.bench.pg_server``) is started for the test session, one per xdist worker, in
a temporary directory: as root (CI) it runs as the ``postgres`` user, since ``initdb`` refuses
root. It listens on 127.0.0.1 on a free port, and is stopped and deleted at the end. Missing
binaries fail the tests that need them, saying what is missing: nothing is skipped.
"""
from __future__ import annotations

from dataclasses import replace
from datetime import datetime, timedelta, timezone
import pytest

from lupin.bench.pg_server import PostgresServer, PostgresUnavailable
from mission.history.records import Observation, PatrolStart
from mission.history.store import History, open_history

T0 = datetime(2025, 5, 1, 6, 0, tzinfo=timezone.utc)


def obs(pot: str, seq: int = 1, status: str = "inspected", color: str | None = "red", blooms: int | None = 1,
        bug: bool | None = False, x: float = 0.0, y: float = 0.0, facing: float = 0.0, tag: int | None = None,
        anomalies: tuple[str, ...] = (), when: datetime = T0) -> Observation:
    """An observation as a test writes it; an uninspected pot has no flower."""
    if status != "inspected":
        color, blooms, bug = None, None, None
    return Observation(pot_id=pot, seq=seq, observed_at=when, status=status, flower_color=color, blooms=blooms,
                       bug=bug, x=x, y=y, facing=facing, tag_expected=tag, anomalies=anomalies,
                       confidence=0.9 if color else None)


def add_patrol(history: History, rows: list[Observation], mission: str = "m", robot: str = "mirte",
               started: datetime = T0, outcome: str | None = "completed", report_path: str | None = None,
               world: str | None = "w") -> int:
    """One whole patrol with ``rows`` (their seq renumbered in order), ended unless ``outcome`` is
    None; in the sim world ``world`` (None: on the robot)."""
    pid = history.begin_patrol(PatrolStart(robot, mission, world, report_path, len(rows)), started_at=started)
    history.add_observations(pid, [replace(o, seq=k + 1, observed_at=started) for k, o in enumerate(rows)])
    if outcome is not None:
        history.end_patrol(pid, outcome, 100.0, 10.0, ended_at=started + timedelta(minutes=5))
    return pid


@pytest.fixture
def sqlite_history(tmp_path) -> History:
    h = open_history(str(tmp_path / "h.db"))
    yield h
    h.close()



# --- PostgreSQL ------------------------------------------------------------------------------------
@pytest.fixture(scope="session")
def postgres() -> PostgresServer:
    try:
        server = PostgresServer()
    except PostgresUnavailable as exc:  # a failure that says what is missing, never a skip
        pytest.fail(str(exc), pytrace=False)
    yield server
    server.stop()


@pytest.fixture
def pg_url(postgres) -> str:
    return postgres.new_database()
