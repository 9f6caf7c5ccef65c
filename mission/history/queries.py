"""The grower's questions as SQL (SQLAlchemy Core), each a function of an open connection.

Each reads only what it needs through an index (``schema.INDEXES``): a year of 4 patrols a day
over 2,000 pots is ~2.9 M observations, and none of these scans them. "The latest" is by
``started_at`` (then id); a mission's patrols are those recorded under its name, whichever
robot ran them.
"""
from __future__ import annotations

from collections import defaultdict

from sqlalchemy import Connection, case, func, select

from mission.history.changes import patrol_changes
from mission.history.records import (ChangeSet, Observation, Patrol, PestMap, PestPressure, TimelineEntry, as_utc)
from mission.history.schema import observations as O
from mission.history.schema import patrols as P

NEWEST_FIRST = (P.c.started_at.desc(), P.c.id.desc())


def _patrol(r, observed: int | None = None, pests: int | None = None) -> Patrol:
    m = r._mapping
    return Patrol(m["id"], m["robot"], m["mission"], m["world"], as_utc(m["started_at"]), as_utc(m["ended_at"]),
                  m["outcome"], m["sim_time_s"], m["distance_m"], m["report_path"], m["pots"], observed, pests)


def patrol(conn: Connection, patrol_id: int) -> Patrol | None:
    r = conn.execute(select(P).where(P.c.id == patrol_id)).first()
    return None if r is None else _patrol(r)


def patrols(conn: Connection, mission: str | None = None, robot: str | None = None,
            limit: int | None = None) -> list[Patrol]:
    """Patrols, newest first, each with its rows counted (those of the patrols listed only)."""
    q = select(P).order_by(*NEWEST_FIRST)
    if mission is not None:
        q = q.where(P.c.mission == mission)
    if robot is not None:
        q = q.where(P.c.robot == robot)
    if limit is not None:
        q = q.limit(limit)
    rows = conn.execute(q).all()
    counts: dict[int, tuple[int, int]] = {}
    ids = [r.id for r in rows]
    for chunk in (ids[i:i + 500] for i in range(0, len(ids), 500)):
        agg = select(O.c.patrol_id, func.count(), func.sum(case((O.c.bug == True, 1), else_=0)))  # noqa: E712
        for pid, n, pests in conn.execute(agg.where(O.c.patrol_id.in_(chunk)).group_by(O.c.patrol_id)):
            counts[pid] = (n, int(pests or 0))
    return [_patrol(r, *counts.get(r.id, (0, 0))) for r in rows]


def latest_mission(conn: Connection) -> str | None:
    """The mission of the latest patrol: what "the last patrols" mean when no mission is named."""
    return conn.execute(select(P.c.mission).order_by(*NEWEST_FIRST).limit(1)).scalar()


def latest_patrols(conn: Connection, mission: str, n: int, before: Patrol | None = None) -> list[Patrol]:
    """The last ``n`` patrols of ``mission``, newest first; with ``before``, those started before it."""
    q = select(P).where(P.c.mission == mission)
    if before is not None:
        q = q.where(P.c.id != before.id, P.c.started_at <= before.started_at)
    return [_patrol(r) for r in conn.execute(q.order_by(*NEWEST_FIRST).limit(n))]


def observations(conn: Connection, patrol_id: int) -> list[Observation]:
    """One patrol's rows in the order its pots were recorded."""
    q = select(O).where(O.c.patrol_id == patrol_id).order_by(O.c.seq)
    return [Observation.from_row(r) for r in conn.execute(q)]


def pot_timeline(conn: Connection, pot_id: str, mission: str | None = None) -> list[TimelineEntry]:
    """Every observation of one pot, oldest first, with the patrol it was on."""
    q = (select(O, P.c.mission, P.c.robot, P.c.started_at).join(P, P.c.id == O.c.patrol_id)
         .where(O.c.pot_id == pot_id).order_by(P.c.started_at, P.c.id))
    if mission is not None:
        q = q.where(P.c.mission == mission)
    out = []
    for r in conn.execute(q):
        m = r._mapping
        out.append(TimelineEntry(m["patrol_id"], m["mission"], m["robot"], as_utc(m["started_at"]),
                                 Observation.from_row({k: m[k] for k in O.c.keys()})))
    return out


def changes(conn: Connection, mission: str | None = None) -> ChangeSet:
    """What changed between the last two patrols of ``mission`` (default: the latest patrol's)."""
    mission = mission or latest_mission(conn)
    if mission is None:
        return ChangeSet(None, None)
    last = latest_patrols(conn, mission, 2)
    if not last:
        return ChangeSet(None, None)
    if len(last) == 1:
        return ChangeSet(last[0], None)
    after, before = last
    prior = {o.pot_id: o for o in observations(conn, before.id)}
    return ChangeSet(after, before, tuple(patrol_changes(prior, observations(conn, after.id))))


def pest_map(conn: Connection, last: int, mission: str | None = None) -> PestMap:
    """Each pot's pest pressure over the last ``last`` patrols of ``mission`` (default: the latest
    patrol's): how many of them judged its flower, how many saw a pest, the current streak, and
    where the pot stood when last seen."""
    mission = mission or latest_mission(conn)
    if mission is None:
        return PestMap(None, ())
    chosen = latest_patrols(conn, mission, last)
    rank = {p.id: k for k, p in enumerate(chosen)}  # 0: the latest
    q = select(O.c.patrol_id, O.c.pot_id, O.c.bug, O.c.x, O.c.y, O.c.facing, O.c.tag_expected, O.c.tag_read,
               O.c.seq).where(O.c.patrol_id.in_(list(rank)))
    seen: dict[str, list] = defaultdict(list)
    for r in conn.execute(q):
        seen[r.pot_id].append(r)
    pots = []
    for pot_id, rows in seen.items():
        rows.sort(key=lambda r: rank[r.patrol_id])
        judged = [bool(r.bug) for r in rows if r.bug is not None]
        streak = 0
        for r in rows:
            if r.bug is not True:
                break
            streak += 1
        where = next((r for r in rows if r.x is not None), rows[0])
        tag = next((r.tag_expected for r in rows if r.tag_expected is not None), None)
        pots.append((rows[0].seq if rank[rows[0].patrol_id] == 0 else 10**9,
                     PestPressure(pot_id, where.x, where.y, where.facing, tag, len(judged), sum(judged), streak)))
    pots.sort(key=lambda sp: (sp[0], sp[1].pot_id))
    return PestMap(mission, tuple(chosen), tuple(p for _, p in pots))


def previous_observations(conn: Connection, mission: str) -> tuple[Patrol | None, dict[str, Observation]]:
    """The latest patrol of ``mission`` so far and its rows by pot: what a starting patrol's
    ``changes`` are against."""
    last = latest_patrols(conn, mission, 1)
    if not last:
        return None, {}
    return last[0], {o.pot_id: o for o in observations(conn, last[0].id)}


def pots_known(conn: Connection, mission: str | None = None, limit: int = 20) -> list[str]:
    """Some pot ids the history knows (for a message naming what exists)."""
    q = select(O.c.pot_id).distinct().order_by(O.c.pot_id).limit(limit)
    if mission is not None:
        q = q.join(P, P.c.id == O.c.patrol_id).where(P.c.mission == mission)
    return list(conn.execute(q).scalars())


def count(conn: Connection) -> tuple[int, int]:
    """(patrols, observations) in the database."""
    return (conn.execute(select(func.count()).select_from(P)).scalar() or 0,
            conn.execute(select(func.count()).select_from(O)).scalar() or 0)



def missions(conn: Connection) -> list[str]:
    """Every mission with a patrol, the latest patrolled first."""
    q = select(P.c.mission, func.max(P.c.started_at).label("last")).group_by(P.c.mission).order_by(
        func.max(P.c.started_at).desc())
    return [r.mission for r in conn.execute(q)]
