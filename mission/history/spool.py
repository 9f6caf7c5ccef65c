"""The history's local spool: writes that the database could not take yet, kept in order in a
small SQLite file (``history.spool`` in the runtime's state directory, spec/history.md), so a farm
server that is down at start or drops out mid-patrol never stops the robot and loses nothing.

One table, ``waiting``: a row per write (:mod:`mission.history.writes`, as JSON), numbered in
the order it was kept, with the database it is for (the URL as shown, password hidden: rows kept
for one database are never sent to another). Writes are taken out only after the database has
committed them, so a crash between the two sends them again, which is a no-op.

SQLite, not a file of lines: each append is one transaction, so a process killed while writing
leaves the spool as it was, and ``lupin history sync`` in another process can read it while the
runtime writes (WAL, a busy wait).
"""
from __future__ import annotations

import json
import sqlite3
import threading
from pathlib import Path
from typing import Sequence

from hw.errors import InputError
from mission.history.writes import Write, from_json

FILE_NAME = "history.spool"


class Spool:
    """The writes waiting for a database, oldest first."""

    def __init__(self, path: Path):
        """Open (or make) the spool at ``path``; InputError naming it when it cannot be used:
        a local file the runtime cannot write is bad input, not an outage."""
        self.path = Path(path)
        self._lock = threading.Lock()
        try:
            self._db = sqlite3.connect(self.path, timeout=30.0, isolation_level=None, check_same_thread=False)
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("CREATE TABLE IF NOT EXISTS waiting (n INTEGER PRIMARY KEY AUTOINCREMENT, "
                             "database TEXT NOT NULL, write TEXT NOT NULL)")
            self._db.execute("BEGIN IMMEDIATE")  # proven writable now, not at the first outage
            self._db.execute("ROLLBACK")
        except sqlite3.Error as exc:
            raise InputError(f"history spool {self.path}: cannot use it: {exc}") from None

    def append(self, database: str, writes: Sequence[Write]) -> None:
        """Keep ``writes`` for ``database``, after everything kept before, in one transaction."""
        if not writes:
            return
        with self._lock:
            self._db.execute("BEGIN IMMEDIATE")
            try:
                self._db.executemany("INSERT INTO waiting (database, write) VALUES (?, ?)",
                                     [(database, json.dumps(w.as_json())) for w in writes])
            except BaseException:
                self._db.execute("ROLLBACK")
                raise
            self._db.execute("COMMIT")

    def oldest(self, database: str, limit: int) -> list[tuple[int, Write]]:
        """Up to ``limit`` of ``database``'s writes, oldest first, each with its number."""
        with self._lock:
            rows = self._db.execute("SELECT n, write FROM waiting WHERE database = ? ORDER BY n LIMIT ?",
                                    (database, limit)).fetchall()
        return [(n, from_json(json.loads(text))) for n, text in rows]

    def remove(self, database: str, up_to: int) -> None:
        """Forget ``database``'s writes numbered up to ``up_to`` (the database has them)."""
        with self._lock:
            self._db.execute("DELETE FROM waiting WHERE database = ? AND n <= ?", (database, up_to))

    def count(self, database: str) -> int:
        """Writes waiting for ``database``."""
        with self._lock:
            return self._db.execute("SELECT count(*) FROM waiting WHERE database = ?", (database,)).fetchone()[0]

    def rows(self, database: str) -> int:
        """Rows waiting for ``database``: each pot's row, each patrol's start and end."""
        with self._lock:
            texts = [t for (t,) in self._db.execute("SELECT write FROM waiting WHERE database = ?", (database,))]
        return sum(len(d["rows"]) if d.get("op") == "rows" else 1 for d in map(json.loads, texts))

    def databases(self) -> dict[str, int]:
        """Every database something waits for, with how many writes."""
        with self._lock:
            return dict(self._db.execute("SELECT database, count(*) FROM waiting GROUP BY database ORDER BY min(n)"))

    def close(self) -> None:
        with self._lock:
            self._db.close()


class MemorySpool(Spool):
    """The same, in memory: for a history opened without a state directory (a benchmark, a
    test, a reading command). Nothing survives the process."""

    def __init__(self):
        self.path = None
        self._lock = threading.Lock()
        self._db = sqlite3.connect(":memory:", isolation_level=None, check_same_thread=False)
        self._db.execute("CREATE TABLE waiting (n INTEGER PRIMARY KEY AUTOINCREMENT, database TEXT NOT NULL, "
                         "write TEXT NOT NULL)")


def open_spool(directory: Path) -> Spool:
    """The spool in the state directory ``directory``."""
    return Spool(Path(directory) / FILE_NAME)


def runtime_spool(runtime, backend: str) -> Spool:
    """The spool of a runtime (``runtime``: its ``RuntimeConfig``) on ``backend``: in its state
    directory when it has one that outlives the run (the robot's, or one the config names), else
    in memory. A sim run's own state directory is fresh and thrown away, so a spool there would
    be found by no later command: it only left a directory in the temp dir per patrol."""
    if backend != "hw" and runtime.state_dir is None:
        return MemorySpool()
    from mission.runtime.state_dir import state_directory

    return open_spool(state_directory(runtime, backend))
