"""Shared builders for the history tests: a hand-built history (patrols and their rows, as a
test says), and a real PostgreSQL 15 server on loopback.

The server is started for the test session (one per xdist worker) in a temporary directory:
``initdb`` refuses to run as root, so as root (CI) the directory is given to the ``postgres``
user and the server runs as it (``runuser``); as anyone else it runs as that user. It listens on
127.0.0.1 on a free port with trust authentication (loopback only, a throwaway cluster), and is
stopped and deleted at the end. Missing binaries fail the tests that need them, saying what is
missing: nothing is skipped.
"""
from __future__ import annotations

import os
import shutil
import socket
import subprocess
import tempfile
import uuid
from datetime import datetime, timedelta, timezone
from pathlib import Path

import pytest

from mission.history.records import Observation, PatrolStart
from mission.history.store import History, open_history

PG_BIN = Path(os.environ.get("LUPIN_PG_BIN", "/usr/lib/postgresql/15/bin"))
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
               started: datetime = T0, outcome: str | None = "completed", report_path: str | None = None) -> int:
    """One whole patrol with ``rows`` (their seq renumbered in order), ended unless ``outcome`` is None."""
    pid = history.begin_patrol(PatrolStart(robot, mission, "w", report_path, len(rows)), started_at=started)
    history.add_observations(pid, [Observation(**{**o.__dict__, "seq": k + 1, "observed_at": started})
                                    for k, o in enumerate(rows)])
    if outcome is not None:
        history.end_patrol(pid, outcome, 100.0, 10.0, ended_at=started + timedelta(minutes=5))
    return pid


@pytest.fixture
def sqlite_history(tmp_path) -> History:
    h = open_history(str(tmp_path / "h.db"))
    yield h
    h.close()


# --- PostgreSQL ------------------------------------------------------------------------------------
def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class PostgresServer:
    def __init__(self):
        missing = [b for b in ("initdb", "pg_ctl", "postgres") if not (PG_BIN / b).is_file()]
        if missing:
            pytest.fail(f"PostgreSQL 15 server binaries missing in {PG_BIN} ({', '.join(missing)}): install the "
                        f"postgresql-15 package (or set LUPIN_PG_BIN to its bin directory)", pytrace=False)
        self.root = Path(tempfile.mkdtemp(prefix="lupin-pg-"))
        self.data, self.port = self.root / "data", _free_port()
        self.as_user: list[str] = []
        if os.geteuid() == 0:
            if shutil.which("runuser") is None:
                pytest.fail("running as root and runuser is missing: initdb refuses root", pytrace=False)
            shutil.chown(self.root, "postgres", "postgres")
            os.chmod(self.root, 0o700)
            self.as_user = ["runuser", "-u", "postgres", "--"]
        self._run("initdb", "-D", str(self.data), "-U", "lupin", "--auth=trust", "-E", "UTF8", "--no-sync")
        self._run("pg_ctl", "-D", str(self.data), "-l", str(self.root / "log"), "-w", "-t", "60", "-o",
                  f"-p {self.port} -k {self.root} -c listen_addresses=127.0.0.1 -c fsync=off", "start")
        self.url = f"postgresql://lupin@127.0.0.1:{self.port}/postgres"

    def _run(self, binary: str, *args: str) -> None:
        cmd = [*self.as_user, str(PG_BIN / binary), *args]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=self.root)
        if done.returncode != 0:
            log = (self.root / "log").read_text()[-2000:] if (self.root / "log").exists() else ""
            pytest.fail(f"{binary} failed ({done.returncode}): {done.stderr.strip()[-2000:]}\n{log}", pytrace=False)

    def new_database(self) -> str:
        """A fresh database on the server: its URL."""
        import psycopg

        name = f"t_{uuid.uuid4().hex[:12]}"
        with psycopg.connect(self.url.replace("postgresql://", "postgresql://", 1), autocommit=True) as conn:
            conn.execute(f"CREATE DATABASE {name}")
        return self.url.rsplit("/", 1)[0] + "/" + name

    def stop(self) -> None:
        try:
            subprocess.run([*self.as_user, str(PG_BIN / "pg_ctl"), "-D", str(self.data), "-m", "immediate", "-w",
                            "stop"], capture_output=True, timeout=60, cwd=self.root)
        finally:
            shutil.rmtree(self.root, ignore_errors=True)


@pytest.fixture(scope="session")
def postgres() -> PostgresServer:
    server = PostgresServer()
    yield server
    server.stop()


@pytest.fixture
def pg_url(postgres) -> str:
    return postgres.new_database()
