"""What the history hands back: plain records (no database objects leak out), each with
``as_json`` for ``--json`` and for the link. The ones a query makes thousands of (observations,
timeline entries, pest pressures) are slotted, not frozen: a frozen dataclass's ``__init__``
costs ~6 us for 17 fields against ~1 us, and a year's timeline is 1,500 of them. Treat them as
read-only all the same."""
from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields
from datetime import datetime, timezone
from typing import ClassVar


def as_utc(t: datetime | None) -> datetime | None:
    """A timestamp from either database as an aware UTC datetime (SQLite hands back naive ones)."""
    if t is None:
        return None
    return t.replace(tzinfo=timezone.utc) if t.tzinfo is None else t.astimezone(timezone.utc)


def iso(t: datetime | None) -> str | None:
    return None if t is None else as_utc(t).isoformat(timespec="seconds").replace("+00:00", "Z")


def _json(record) -> dict:
    return {k: iso(v) if isinstance(v, datetime) else list(v) if isinstance(v, tuple) else v
            for k, v in asdict(record).items()}


@dataclass(frozen=True)
class PatrolStart:
    """What is known of a patrol when it starts."""
    robot: str
    mission: str
    world: str | None
    report_path: str | None
    pots: int | None = None


@dataclass(frozen=True)
class Patrol:
    id: int
    robot: str
    mission: str
    world: str | None
    started_at: datetime
    ended_at: datetime | None
    outcome: str | None
    sim_time_s: float | None
    distance_m: float | None
    report_path: str | None
    pots: int | None = None
    observed: int | None = None
    """Rows recorded for it (filled by the queries that count them)."""
    pests: int | None = None
    """Of those, pots with a pest."""

    def as_json(self) -> dict:
        return _json(self)


@dataclass(slots=True)
class Observation:
    """One pot in one patrol (spec/history.md ``observations``)."""
    pot_id: str
    seq: int
    observed_at: datetime
    status: str
    tag_read: int | None = None
    flower_color: str | None = None
    blooms: int | None = None
    bug: bool | None = None
    confidence: float | None = None
    x: float | None = None
    y: float | None = None
    anomalies: tuple[str, ...] = ()
    front_image: str | None = None
    wrist_image: str | None = None
    facing: float | None = None
    tag_expected: int | None = None
    patrol_id: int | None = None

    COLUMNS: ClassVar[tuple[str, ...]] = ()
    """The table's columns in the order of this record's fields (``from_tuple`` reads them)."""

    @classmethod
    def from_tuple(cls, r) -> "Observation":
        """A row selected as ``COLUMNS``: the fast path for a patrol's thousands of rows."""
        (pot_id, seq, observed_at, status, tag_read, color, blooms, bug, confidence, x, y, anomalies, front, wrist,
         facing, tag_expected, patrol_id) = r
        return cls(pot_id, seq, as_utc(observed_at), status, tag_read, color, blooms,
                   None if bug is None else bool(bug), confidence, x, y,
                   tuple(k for k in (anomalies or "").split(",") if k), front, wrist, facing,
                   tag_expected, patrol_id)

    def row(self, patrol_id: int) -> dict:
        """The row to insert, for patrol ``patrol_id``."""
        out = asdict(self)
        out["patrol_id"] = patrol_id
        out["anomalies"] = ",".join(self.anomalies)
        return out

    @classmethod
    def from_row(cls, r) -> "Observation":
        m = dict(r._mapping) if hasattr(r, "_mapping") else dict(r)
        kinds = tuple(k for k in (m.pop("anomalies", "") or "").split(",") if k)
        m["observed_at"] = as_utc(m["observed_at"])
        m["bug"] = None if m.get("bug") is None else bool(m["bug"])
        return cls(**{k: v for k, v in m.items() if k in cls.__dataclass_fields__}, anomalies=kinds)

    @property
    def inspected(self) -> bool:
        return self.status == "inspected"

    def as_json(self) -> dict:
        """``_json``'s answer, field by field (``asdict`` deep-copies: 20 us a row, and a
        patrol's page or a pot's year is 2,000 rows)."""
        out = {name: getattr(self, name) for name in self.COLUMNS}
        out["observed_at"], out["anomalies"] = iso(self.observed_at), list(self.anomalies)
        return out


Observation.COLUMNS = tuple(f.name for f in fields(Observation))


@dataclass(slots=True)
class TimelineEntry:
    """One pot in one patrol, with the patrol it was seen on."""
    patrol: int
    mission: str
    robot: str
    started_at: datetime
    observation: Observation
    world: str | None = None
    """The patrol's sim world; None on the robot (its greenhouse, spec/history.md)."""

    def as_json(self) -> dict:
        return {"patrol": self.patrol, "mission": self.mission, "robot": self.robot, "world": self.world,
                "started_at": iso(self.started_at), **self.observation.as_json()}


@dataclass(frozen=True)
class Change:
    """Something that changed at a pot between two patrols (``mission.history.changes``)."""
    pot: str
    kind: str
    before: object
    after: object
    detail: str

    def as_json(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class ChangeSet:
    """What changed between two patrols of one mission: ``before`` None when there is no earlier one."""
    after: Patrol | None
    before: Patrol | None
    changes: tuple[Change, ...] = ()

    def as_json(self) -> dict:
        return {"after": self.after.as_json() if self.after else None,
                "before": self.before.as_json() if self.before else None,
                "changes": [c.as_json() for c in self.changes]}


@dataclass(slots=True)
class PestPressure:
    """One pot's pest record over the last patrols of a mission."""
    pot_id: str
    x: float | None
    y: float | None
    facing: float | None
    tag: int | None
    observed: int
    """Patrols (of those asked about) that judged this pot's flower (bug known)."""
    pests: int
    """Of those, how many saw a pest."""
    streak: int
    """Consecutive latest patrols that saw a pest (0: the latest saw none, or did not judge)."""

    @property
    def pressure(self) -> float:
        return self.pests / self.observed if self.observed else 0.0

    def as_json(self) -> dict:
        return {**asdict(self), "pressure": round(self.pressure, 4)}


@dataclass(frozen=True)
class PestMap:
    """Pest pressure over the last ``len(patrols)`` patrols of one mission."""
    mission: str | None
    patrols: tuple[Patrol, ...]
    pots: tuple[PestPressure, ...] = field(default_factory=tuple)

    def as_json(self) -> dict:
        return {"mission": self.mission, "patrols": [p.id for p in self.patrols],
                "pots": [p.as_json() for p in self.pots]}
