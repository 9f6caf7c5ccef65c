"""What a patrol asks the history to write, as plain data: a patrol's start, its pots' rows, its
end. Each names the patrol by the id the robot gave it (``uid``, a UUID made when it starts), not
by the database's integer id, so a write can wait in the spool (:mod:`mission.history.spool`)
while the server is down and be sent later, and sending it twice is a no-op: the patrol is found
by its uid, a pot's row by (patrol, pot), an end is an update (spec/history.md).

Each has ``as_json``/:func:`from_json` for the spool's file: timestamps as ISO text.
"""
from __future__ import annotations

import uuid
from dataclasses import asdict, dataclass
from datetime import datetime
from typing import Union

from mission.history.records import Observation, PatrolStart, as_utc


def new_uid() -> str:
    """A patrol's own id: unique across robots and runs without asking the database."""
    return uuid.uuid4().hex


def _when(text: str | None) -> datetime | None:
    return None if text is None else as_utc(datetime.fromisoformat(text))


@dataclass(frozen=True)
class Begin:
    """A patrol starts: its ``patrols`` row, ``ended_at`` null."""
    uid: str
    start: PatrolStart
    started_at: datetime

    def as_json(self) -> dict:
        return {"op": "begin", "uid": self.uid, "start": asdict(self.start), "started_at": self.started_at.isoformat()}


@dataclass(frozen=True)
class Rows:
    """Pots recorded: their ``observations`` rows, in the order recorded (``seq``)."""
    uid: str
    rows: tuple[Observation, ...]

    def as_json(self) -> dict:
        out = []
        for o in self.rows:
            row = asdict(o)
            row["observed_at"] = o.observed_at.isoformat()
            row["anomalies"] = list(o.anomalies)
            out.append(row)
        return {"op": "rows", "uid": self.uid, "rows": out}


@dataclass(frozen=True)
class End:
    """A patrol ended: its outcome, time, distance and ``ended_at``, and its legs (the report's
    ``legs`` entries: ``legs`` rows)."""
    uid: str
    outcome: str
    sim_time_s: float | None
    distance_m: float | None
    ended_at: datetime
    legs: tuple[dict, ...] = ()

    def as_json(self) -> dict:
        return {"op": "end", "uid": self.uid, "outcome": self.outcome, "sim_time_s": self.sim_time_s,
                "distance_m": self.distance_m, "ended_at": self.ended_at.isoformat(), "legs": list(self.legs)}


Write = Union[Begin, Rows, End]


def from_json(doc: dict) -> Write:
    """A write as the spool keeps it; ValueError for a document that is none."""
    op = doc.get("op")
    if op == "begin":
        return Begin(doc["uid"], PatrolStart(**doc["start"]), _when(doc["started_at"]))
    if op == "rows":
        rows = tuple(Observation(**{**r, "observed_at": _when(r["observed_at"]), "anomalies": tuple(r["anomalies"])})
                     for r in doc["rows"])
        return Rows(doc["uid"], rows)
    if op == "end":
        return End(doc["uid"], doc["outcome"], doc["sim_time_s"], doc["distance_m"], _when(doc["ended_at"]),
                   tuple(doc.get("legs", ())))
    raise ValueError(f"not a history write: op {op!r}")


def rows_in(writes) -> int:
    """Rows the writes would add or change (a start and an end are one row each)."""
    return sum(len(w.rows) if isinstance(w, Rows) else 1 for w in writes)
