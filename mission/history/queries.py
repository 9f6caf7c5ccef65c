"""The grower's questions as SQL (SQLAlchemy Core), each a function of an open connection.

Each reads only what it needs through an index (``schema.INDEXES``): a year of 4 patrols a day
over 2,000 pots is ~2.9 M observations, and none of these scans them. "The latest" is by
``started_at`` (then id); a mission's patrols are those recorded under its name, whichever
robot ran them, in one greenhouse (spec/history.md): sim patrols of the same world, robot patrols
(``world`` null) with robot patrols. A comparison (``changes``, ``pest_map``, a pot's timeline,
the previous patrol) stays in the greenhouse of the latest patrol it starts from, unless asked
for ``every`` greenhouse (``--all``): a test patrol in the sim is never compared with the robot's
real patrols of a mission of the same name.
"""
from __future__ import annotations

from collections import defaultdict
from datetime import timedelta

from sqlalchemy import Connection, and_, case, func, or_, select

from mission.history.changes import pot_changes
from mission.history.records import (Change, ChangeSet, Observation, Patrol, PestMap, PestPressure, TimelineEntry,
                                     as_utc)
from mission.history.schema import observations as O
from mission.history.schema import patrols as P

NEWEST_FIRST = (P.c.started_at.desc(), P.c.id.desc())


class _Every:
    def __repr__(self) -> str:
        return "EVERY"


EVERY = _Every()
"""No greenhouse chosen: patrols of every world and the robot's alike."""


def in_greenhouse(world):
    """The clause choosing one greenhouse's patrols: the sim world ``world``, or the robot's
    (``world`` None); none for :data:`EVERY`."""
    if world is EVERY:
        return None
    return P.c.world.is_(None) if world is None else P.c.world == world
# Results of thousands of rows are taken with .all(): one fetchall in the driver, where iterating
# a result fetches row by row (4,000 calls, a third of a query's time on a year's database).


def _patrol(r, observed: int | None = None, pests: int | None = None) -> Patrol:
    m = r._mapping
    return Patrol(m["id"], m["robot"], m["mission"], m["world"], as_utc(m["started_at"]), as_utc(m["ended_at"]),
                  m["outcome"], m["sim_time_s"], m["distance_m"], m["report_path"], m["pots"], observed, pests)


def patrol(conn: Connection, patrol_id: int) -> Patrol | None:
    r = conn.execute(select(P).where(P.c.id == patrol_id)).first()
    return None if r is None else _patrol(r)


def patrols(conn: Connection, mission: str | None = None, robot: str | None = None,
            limit: int | None = None, offset: int = 0) -> list[Patrol]:
    """Patrols, newest first (from the ``offset``-th), each with its rows counted (those of the
    patrols listed only)."""
    q = select(P).order_by(*NEWEST_FIRST)
    if mission is not None:
        q = q.where(P.c.mission == mission)
    if robot is not None:
        q = q.where(P.c.robot == robot)
    if limit is not None:
        q = q.limit(limit)
    if offset:
        q = q.offset(offset)
    rows = conn.execute(q).all()
    counts = _row_counts(conn, [r.id for r in rows])
    return [_patrol(r, *counts.get(r.id, (0, 0))) for r in rows]


def _row_counts(conn: Connection, ids: list[int]) -> dict[int, tuple[int, int]]:
    """(rows, rows with a pest) of each patrol in ``ids``, counted by the database over the
    primary key's patrol_id prefix."""
    counts: dict[int, tuple[int, int]] = {}
    for chunk in (ids[i:i + 500] for i in range(0, len(ids), 500)):
        agg = select(O.c.patrol_id, func.count(), func.sum(case((O.c.bug == True, 1), else_=0)))  # noqa: E712
        for pid, n, pests in conn.execute(agg.where(O.c.patrol_id.in_(chunk)).group_by(O.c.patrol_id)):
            counts[pid] = (n, int(pests or 0))
    return counts


def pest_trend(conn: Connection, latest: Patrol, days: float = 28.0, points: int = 28) -> list[Patrol]:
    """The count of pots with a pest, patrol by patrol, over the ``days`` up to ``latest`` in its
    mission and greenhouse, oldest first: at most ``points`` patrols, evenly thinned (a year's
    database has 4 a day; counting 28 patrols reads 28 patrols' rows by the primary key, not a
    month's 112)."""
    q = (select(P.c.id).where(P.c.mission == latest.mission, P.c.started_at <= latest.started_at,
                              P.c.started_at >= latest.started_at - timedelta(days=days))
         .order_by(P.c.started_at, P.c.id))
    if (clause := in_greenhouse(latest.world)) is not None:
        q = q.where(clause)
    ids = list(conn.execute(q).scalars())
    if len(ids) > points:  # evenly spaced, the latest kept
        step = (len(ids) - 1) / (points - 1)
        ids = [ids[round(k * step)] for k in range(points)]
    chosen = {r.id: r for r in conn.execute(select(P).where(P.c.id.in_(ids))).all()}
    counts = _row_counts(conn, ids)
    return [_patrol(chosen[i], *counts.get(i, (0, 0))) for i in ids]


def latest_mission(conn: Connection) -> str | None:
    """The mission of the latest patrol: what "the last patrols" mean when no mission is named."""
    return conn.execute(select(P.c.mission).order_by(*NEWEST_FIRST).limit(1)).scalar()


def latest_patrols(conn: Connection, mission: str, n: int, before: Patrol | None = None, world=EVERY) -> list[Patrol]:
    """The last ``n`` patrols of ``mission``, newest first; with ``before``, those started before
    it; with ``world``, only that greenhouse's (:func:`in_greenhouse`)."""
    q = select(P).where(P.c.mission == mission)
    if (clause := in_greenhouse(world)) is not None:
        q = q.where(clause)
    if before is not None:
        q = q.where(P.c.id != before.id, P.c.started_at <= before.started_at)
    return [_patrol(r) for r in conn.execute(q.order_by(*NEWEST_FIRST).limit(n))]


def observations(conn: Connection, patrol_id: int) -> list[Observation]:
    """One patrol's rows in the order its pots were recorded."""
    q = select(*(O.c[name] for name in Observation.COLUMNS)).where(O.c.patrol_id == patrol_id).order_by(O.c.seq)
    return [Observation.from_tuple(r) for r in conn.execute(q).all()]


def pot_timeline(conn: Connection, pot_id: str, mission: str | None = None, every: bool = False) -> list[TimelineEntry]:
    """Every observation of one pot, oldest first, with the patrol it was on, in the greenhouse
    of its latest (unless ``every``): a year is ~1,500 rows, read in the ``(pot_id, patrol_id)``
    index's order and built positionally."""
    q = (select(*(O.c[n] for n in Observation.COLUMNS), P.c.mission, P.c.robot, P.c.started_at, P.c.world)
         .join(P, P.c.id == O.c.patrol_id).where(O.c.pot_id == pot_id).order_by(O.c.patrol_id))
    if mission is not None:
        q = q.where(P.c.mission == mission)
    n = len(Observation.COLUMNS)
    out = []
    for r in conn.execute(q).all():
        o = Observation.from_tuple(r[:n])
        out.append(TimelineEntry(o.patrol_id, r[n], r[n + 1], as_utc(r[n + 2]), o, r[n + 3]))
    out.sort(key=lambda e: (e.started_at, e.patrol))  # in Python: the index gives them by id, unsorted by the database
    if out and not every:
        out = [e for e in out if e.world == out[-1].world]
    return out


def changes(conn: Connection, mission: str | None = None, every: bool = False) -> ChangeSet:
    """What changed between the last patrol of ``mission`` (default: the latest patrol's) and
    the one before it in the same greenhouse (any, with ``every``)."""
    mission = mission or latest_mission(conn)
    if mission is None:
        return ChangeSet(None, None)
    last = latest_patrols(conn, mission, 1)
    if not last:
        return ChangeSet(None, None)
    after = last[0]
    earlier = latest_patrols(conn, mission, 1, before=after, world=EVERY if every else after.world)
    if not earlier:
        return ChangeSet(after, None)
    before = earlier[0]
    return ChangeSet(after, before, tuple(changed(conn, before.id, after.id)))


def changed(conn: Connection, before: int, after: int) -> list[Change]:
    """The changes from patrol ``before`` to patrol ``after``, in ``after``'s order. The database
    pairs the two patrols' rows by pot and hands back only the pairs where something a change
    is made of differs (status, pest, colour, blooms); ``mission.history.changes`` then says
    what changed, so the rules live in one place."""
    a, b = O.alias("a"), O.alias("b")
    cols = Observation.COLUMNS
    q = (select(*(a.c[n] for n in cols), *(b.c[n] for n in cols))
         .join_from(b, a, and_(a.c.pot_id == b.c.pot_id, a.c.patrol_id == before))
         .where(b.c.patrol_id == after,
                or_(*(a.c[n].is_distinct_from(b.c[n]) for n in ("status", "bug", "flower_color", "blooms"))))
         .order_by(b.c.seq))
    out: list[Change] = []
    for r in conn.execute(q).all():
        out += pot_changes(Observation.from_tuple(r[:len(cols)]), Observation.from_tuple(r[len(cols):]))
    return out


def pest_map(conn: Connection, last: int, mission: str | None = None, every: bool = False,
             as_of: Patrol | None = None) -> PestMap:
    """Each pot's pest pressure over the last ``last`` patrols of ``mission`` (default: the latest
    patrol's) in the latest one's greenhouse (any, with ``every``): how many of them judged its
    flower, how many saw a pest, the current streak, and where the pot stood when last seen.
    Counted by the database (one pass over the patrols' rows, by the primary key); only the pest
    rows come back for the streaks. ``as_of``: as it stood at that patrol (it and those before)."""
    mission = (as_of.mission if as_of else None) or mission or latest_mission(conn)
    if mission is None:
        return PestMap(None, ())
    latest = [as_of] if as_of is not None else latest_patrols(conn, mission, 1)
    world = EVERY if every or not latest else latest[0].world
    chosen = latest + latest_patrols(conn, mission, last - 1, before=as_of, world=world) if as_of is not None else \
        latest_patrols(conn, mission, last, world=world)
    rank = {p.id: k for k, p in enumerate(chosen)}  # 0: the latest
    in_chosen = O.c.patrol_id.in_(list(rank))
    counts = {pot_id: (judged, int(pests or 0)) for pot_id, judged, pests in conn.execute(
        select(O.c.pot_id, func.count(O.c.bug), func.sum(case((O.c.bug == True, 1), else_=0)))  # noqa: E712
        .where(in_chosen).group_by(O.c.pot_id)).all()}
    pest_at: dict[str, set[int]] = defaultdict(set)
    pest_rows = select(O.c.pot_id, O.c.patrol_id).where(in_chosen, O.c.bug == True)  # noqa: E712
    for pot_id, pid in conn.execute(pest_rows).all():
        pest_at[pot_id].add(rank[pid])
    where_cols = (O.c.pot_id, O.c.x, O.c.y, O.c.facing, O.c.tag_expected)
    where = {r[0]: r for r in conn.execute(select(*where_cols).where(O.c.patrol_id == chosen[0].id)
                                           .order_by(O.c.seq)).all()} if chosen else {}
    missing = [p for p in counts if p not in where]
    for chunk in (missing[i:i + 500] for i in range(0, len(missing), 500)):  # not seen by the latest patrol
        for r in conn.execute(select(*where_cols).join(P, P.c.id == O.c.patrol_id)
                              .where(in_chosen, O.c.pot_id.in_(chunk)).order_by(P.c.started_at.desc())):
            where.setdefault(r[0], r)
    pots = []
    for pot_id, x, y, facing, tag in where.values():
        judged, pests = counts.get(pot_id, (0, 0))
        streak = 0
        if pests:
            hits = pest_at[pot_id]
            while streak in hits:
                streak += 1
        pots.append(PestPressure(pot_id, x, y, facing, tag, judged, pests, streak))
    return PestMap(mission, tuple(chosen), tuple(pots))


def previous_observations(conn: Connection, mission: str, world=EVERY) -> tuple[Patrol | None, dict[str, Observation]]:
    """The latest patrol of ``mission`` so far in the greenhouse ``world`` (the sim world's name;
    None: the robot's) and its rows by pot: what a starting patrol's ``changes`` are against."""
    last = latest_patrols(conn, mission, 1, world=world)
    if not last:
        return None, {}
    return last[0], {o.pot_id: o for o in observations(conn, last[0].id)}


def pots_known(conn: Connection, mission: str | None = None, limit: int = 20) -> list[str]:
    """Some pot ids the history knows, for a message naming what exists: those of the latest
    patrol (of ``mission``), by the primary key, not a scan of every row."""
    latest = select(P.c.id).order_by(*NEWEST_FIRST).limit(1)
    if mission is not None:
        latest = latest.where(P.c.mission == mission)
    pid = conn.execute(latest).scalar()
    if pid is None:
        return []
    q = select(O.c.pot_id).where(O.c.patrol_id == pid).order_by(O.c.pot_id).limit(limit)
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
