"""History benchmarks (issue 22): the grower's questions on a year of patrols, and what
recording costs a patrol.

``history.query``: a synthetic year, 4 patrols a day over 2,000 pots (1,460 patrols, ~2.9 M
observations, pests spreading from a few outbreaks, realistic image paths), built through the
history's own migrations, in SQLite and in PostgreSQL 15 (a throwaway server on loopback,
``lupin.bench.pg_server``); then, each ``QUERIES`` times through :class:`History` as ``lupin
history`` asks them, each time of a different pot or patrol (never a warm repeat): one pot's
timeline over the year, ``changes`` into a patrol from the one before it, ``pests`` over the 10
patrols up to a patrol. Median and p95 of each (goal <= 100 ms), the same on a cold start
(``cold_ms``: the first question on a freshly opened history, a new engine and connection), and
the database's size. The benchmark's median and p95 are SQLite's warm questions.

``history.write``: the added time per pot during a patrol, on SQLite and on PostgreSQL 15 (a
throwaway server on loopback, ``lupin.bench.pg_server``, fsync on so a commit costs what it
would on a farm server's disk): a 2,000-pot patrol recorded through
:class:`~mission.history.recorder.PatrolRecorder` exactly as the patrol does, after 10 earlier
patrols of the same mission, one pot at a time. Two figures per database: ``thread_ms``, the
time the patrol's own thread spends per pot (the row, its changes, the hand-off: what the robot
waits for), and ``commit_ms``, the writer thread's transaction per pot (durable on disk).
The benchmark's median and p95 are the patrol thread's on SQLite.

Both report the machine's 1-minute load average at the end: on a shared 2-core machine a load of
6 makes every wall figure here about three times what it is on an idle one; ``history.query``
also gives each question's process CPU time (``cpu_ms``), what it costs whatever else runs.
"""
from __future__ import annotations

import os
import random
import tempfile
import time
from datetime import datetime, timedelta, timezone
from pathlib import Path
from typing import Callable

import numpy as np

from lupin.bench import Sample, benchmark
from mission.history import queries
from mission.history.queries import count
from mission.history.schema import patrols
from mission.history.recorder import start_recording
from mission.history.store import History, open_history
from mission.patrol.mission_file import Mission, MissionPot
from mission.runtime.config import LupinConfig

POTS, DAYS, PER_DAY = 2000, 365, 4
ROWS, PER_ROW, ROW_GAP, POT_GAP = 20, 100, 1.2, 0.4
QUERIES = 30
PESTS_LAST = 10
START = datetime(2025, 1, 1, 6, 0, tzinfo=timezone.utc)
TAGS = 587
COLORS = np.array(["red", "white", "pink"])
RUNS = "/var/lib/lupin/runs"


def _stats(ms: list[float]) -> dict:
    a = np.asarray(ms)
    return {"median": round(float(np.median(a)), 3), "p95": round(float(np.percentile(a, 95)), 3), "n": int(a.size)}


def _grid() -> tuple[list[str], np.ndarray]:
    ids = [f"P{k:04d}" for k in range(POTS)]
    xy = np.array([((k % PER_ROW) * POT_GAP, (k // PER_ROW) * ROW_GAP) for k in range(POTS)])
    return ids, xy


def _outbreaks(rng: np.random.Generator, xy: np.ndarray, days: int) -> list[tuple[int, int, np.ndarray]]:
    """(first day, last day, distance of every pot from the start) of each outbreak."""
    out = []
    for _ in range(8):
        start = int(rng.integers(0, max(1, days - 20)))
        centre = xy[int(rng.integers(0, len(xy)))]
        out.append((start, start + int(rng.integers(20, 60)), np.hypot(*(xy - centre).T)))
    return out


def build_year(history: History, days: int = DAYS, seed: int = 0) -> int:
    """Fill ``history`` with ``days`` of patrols of one 2,000-pot mission; observations written."""
    rng = np.random.default_rng(seed)
    ids, xy = _grid()
    colors = COLORS[rng.integers(0, 3, POTS)]
    outbreaks = _outbreaks(rng, xy, days)
    phase = rng.integers(0, 14, POTS)
    facing = np.where((np.arange(POTS) // PER_ROW) % 2 == 0, -np.pi / 2, np.pi / 2)
    written = 0
    for day in range(days):
        pressure = np.full(POTS, 0.002)
        for first, last, dist in outbreaks:
            if first <= day <= last:
                pressure = np.where(dist <= 0.3 + 0.12 * (day - first), 0.7, pressure)
        rows = []
        with history.engine.connect() as conn, conn.begin():
            for k in range(PER_DAY):
                started = START + timedelta(days=day, hours=4 * k)
                pid = conn.execute(patrols.insert().values(
                    robot="mirte", mission="greenhouse", world=None, started_at=started,
                    ended_at=started + timedelta(minutes=90), outcome="completed", sim_time_s=5400.0, distance_m=410.0,
                    report_path=f"{RUNS}/greenhouse-{day * PER_DAY + k}/report.json", pots=POTS)
                    .returning(patrols.c.id)).scalar_one()
                failed = rng.random(POTS) < 0.005
                bug = (rng.random(POTS) < pressure) & ~failed
                blooms = (day + phase) // 7 % 5
                base = f"{RUNS}/greenhouse-{day * PER_DAY + k}"
                for i in range(POTS):
                    when = started + timedelta(seconds=2.7 * i)
                    if failed[i]:
                        rows.append((pid, ids[i], i + 1, when, "failed", None, None, None, None, None, float(xy[i, 0]),
                                     float(xy[i, 1]), "unreachable", None, None, float(facing[i]), _tag(i)))
                        continue
                    kinds = ("bug" if bug[i] else "") + ("," if bug[i] and blooms[i] == 0 else "") + \
                        ("no_bloom" if blooms[i] == 0 else "")
                    rows.append((pid, ids[i], i + 1, when, "inspected", _tag(i), colors[i] if blooms[i] else "none",
                                 int(blooms[i]), bool(bug[i]), 0.9, float(xy[i, 0]), float(xy[i, 1]), kinds,
                                 f"{base}/{ids[i]}_front.jpg", f"{base}/{ids[i]}_wrist.jpg", float(facing[i]), _tag(i)))
            _bulk(conn, rows)
        written += len(rows)
    return written


COLUMNS = ("patrol_id", "pot_id", "seq", "observed_at", "status", "tag_read", "flower_color", "blooms", "bug",
           "confidence", "x", "y", "anomalies", "front_image", "wrist_image", "facing", "tag_expected")


def _bulk(conn, rows: list[tuple]) -> None:
    """A day's observations at once: SQLite's executemany, PostgreSQL's COPY (a year is 2.9 M rows)."""
    if conn.dialect.name == "postgresql":
        with conn.connection.driver_connection.cursor() as cur:
            with cur.copy(f"COPY observations ({', '.join(COLUMNS)}) FROM STDIN") as copy:
                for r in rows:
                    copy.write_row(r)
        return
    sql = f"INSERT INTO observations ({', '.join(COLUMNS)}) VALUES ({', '.join('?' * len(COLUMNS))})"
    conn.exec_driver_sql(sql, [(*r[:3], _ts(r[3]), *r[4:]) for r in rows])


def _tag(k: int) -> int | None:
    """Pot k's tag: the 36h11 family has 587 ids, so a 2,000-pot greenhouse tags only some."""
    return k if k < TAGS else None


def _ts(t: datetime) -> str:
    """SQLite's text form of a UTC timestamp, as SQLAlchemy writes it."""
    return t.strftime("%Y-%m-%d %H:%M:%S.%f")


def _db_mb(path: Path) -> float:
    return sum(p.stat().st_size for p in path.parent.glob(path.name + "*")) / 1e6


YEAR_ENV = "LUPIN_BENCH_HISTORY_YEAR"
"""A path for the synthetic year: built there when missing, reused when present (building it is
minutes of the benchmark's time); unset, it is built in a temporary directory every run."""


def _ask(h: History, pick: random.Random, ids: list[str], patrol_ids: list[int]) -> dict:
    """The three questions, each timed (wall and CPU ms): a different pot's timeline, the changes
    into a different patrol from the one before it, the pest map as of a different patrol (the
    10 patrols up to it): no question repeats what the last one read."""
    wall: dict[str, list[float]] = {"pot_timeline": [], "changes": [], "pests": []}
    cpu: dict[str, list[float]] = {k: [] for k in wall}
    checks: dict = {}

    def timed(name: str, ask):
        t, c = time.perf_counter(), time.process_time()
        out = ask()
        wall[name].append((time.perf_counter() - t) * 1000)
        cpu[name].append((time.process_time() - c) * 1000)
        return out

    def changes(after: int):
        with h.reading() as c:
            a = queries.patrol(c, after)
            b = queries.latest_patrols(c, a.mission, 1, before=a, world=a.world)
            return queries.changed(c, b[0].id, a.id) if b else []

    def pests(at: int):
        with h.reading() as c:
            return queries.pest_map(c, PESTS_LAST, as_of=queries.patrol(c, at))

    for _ in range(QUERIES):
        pot, after, at = pick.choice(ids), pick.choice(patrol_ids[1:]), pick.choice(patrol_ids[PESTS_LAST:])
        checks["timeline_rows"] = len(timed("pot_timeline", lambda: h.pot_timeline(pot)))
        checks["changes"] = len(timed("changes", lambda: changes(after)))
        checks["pests_patrols"] = len(timed("pests", lambda: pests(at)).patrols)
    return {"wall": wall, "cpu": cpu, "checks": checks}


def _cold(url: str, pick: random.Random, ids: list[str], patrol_ids: list[int], n: int = 10) -> dict[str, list[float]]:
    """Each question asked first thing on a freshly opened history (a new engine, a new
    connection: what a ``lupin history`` command pays), ``n`` times each."""
    out: dict[str, list[float]] = {"pot_timeline": [], "changes": [], "pests": []}
    for name in out:
        for _ in range(n):
            h = open_history(url, create=False)
            first = _ask_one(h, name, pick, ids, patrol_ids)
            out[name].append(first)
            h.close()
    return out


def _ask_one(h: History, name: str, pick: random.Random, ids: list[str], patrol_ids: list[int]) -> float:
    t = time.perf_counter()
    if name == "pot_timeline":
        h.pot_timeline(pick.choice(ids))
    elif name == "changes":
        with h.reading() as c:
            a = queries.patrol(c, pick.choice(patrol_ids[1:]))
            b = queries.latest_patrols(c, a.mission, 1, before=a, world=a.world)
            queries.changed(c, b[0].id, a.id)
    else:
        with h.reading() as c:
            queries.pest_map(c, PESTS_LAST, as_of=queries.patrol(c, pick.choice(patrol_ids[PESTS_LAST:])))
    return (time.perf_counter() - t) * 1000


def _measure(url: str, size_mb: float | None) -> dict:
    h = open_history(url, create=False)  # as `lupin history` opens it
    with h.reading() as c:
        n_patrols, n = count(c)
        patrol_ids = sorted(p for (p,) in c.execute(patrols.select().with_only_columns(patrols.c.id)))
    ids, _ = _grid()
    warm = _ask(h, random.Random(1), ids, patrol_ids)
    h.close()
    cold = _cold(url, random.Random(2), ids, patrol_ids)
    p95 = max(np.percentile(v, 95) for v in (*warm["wall"].values(), *cold.values()))
    return {"patrols": n_patrols, "observations": n, "db_mb": size_mb,
            **{f"{k}_ms": _stats(v) for k, v in warm["wall"].items()},
            "cold_ms": {k: _stats(v) for k, v in cold.items()},
            "cpu_ms": {k: _stats(v) for k, v in warm["cpu"].items()}, **warm["checks"],
            "all_within_goal": bool(p95 <= 100), "_times": [t for v in warm["wall"].values() for t in v]}


def sqlite_year(tmp: Path) -> tuple[Path, float | None]:
    """The synthetic year in SQLite: at ``LUPIN_BENCH_HISTORY_YEAR`` (built there when missing,
    reused when present), else built in ``tmp``; (its path, build seconds or None if reused)."""
    path = Path(os.environ.get(YEAR_ENV) or Path(tmp) / "year.db")
    build_s = None
    if not path.exists():
        h = open_history(str(path))
        t0 = time.perf_counter()
        build_year(h)
        build_s = round(time.perf_counter() - t0, 1)
        with h.engine.connect() as c:
            c.exec_driver_sql("PRAGMA wal_checkpoint(TRUNCATE)")
            c.exec_driver_sql("ANALYZE")
        h.close()
    return path, build_s


def on_postgres_year(measure: Callable[[str], dict]) -> dict:
    """``measure(url)`` on the synthetic year in PostgreSQL 15 (a throwaway server, the year
    built, vacuumed and analysed), with ``build_s`` and ``db_mb``; ``{"error": why}`` when no
    server can be started (a failure is a result)."""
    try:
        from lupin.bench.pg_server import PostgresServer

        server = PostgresServer()
    except Exception as exc:
        return {"error": str(exc)}
    try:
        url = server.new_database()
        h = open_history(url)
        t0 = time.perf_counter()
        build_year(h)
        build_s = round(time.perf_counter() - t0, 1)
        with h.engine.connect().execution_options(isolation_level="AUTOCOMMIT") as c:
            c.exec_driver_sql("VACUUM ANALYZE")
            size = c.exec_driver_sql("SELECT pg_database_size(current_database())").scalar() / 1e6
        h.close()
        return {**measure(url), "db_mb": round(size, 1), "build_s": build_s}
    finally:
        server.stop()


@benchmark("history.query")
def bench_query(config: LupinConfig) -> Sample:
    figures: dict = {"pots": POTS, "pests_last": PESTS_LAST, "goal_ms": 100}
    with tempfile.TemporaryDirectory() as tmp:
        path, build_s = sqlite_year(Path(tmp))
        figures["sqlite"] = {**_measure(str(path), round(_db_mb(path), 1)), "build_s": build_s}
    times = figures["sqlite"].pop("_times")
    figures["postgresql"] = on_postgres_year(lambda url: _measure(url, None))
    figures["postgresql"].pop("_times", None)
    figures["all_within_goal"] = all(f.get("all_within_goal", False) for f in
                                     (figures["sqlite"], figures["postgresql"]))
    figures["load_avg_1m"] = round(os.getloadavg()[0], 2)
    return Sample(times, figures)


WRITE_POTS, WRITE_PRIOR = 2000, 10


def _patrol_cost(history: History, tmp: Path) -> tuple[list[float], list[float], int]:
    """One patrol of ``WRITE_POTS`` recorded pot by pot after ``WRITE_PRIOR`` earlier ones:
    (patrol-thread ms per pot, writer commit ms per pot, write errors)."""
    ids, xy = _grid()
    m = Mission(name="greenhouse", pots=[MissionPot(id=i, x=float(x), y=float(y), facing=0.0, tag=_tag(k))
                                         for k, (i, (x, y)) in enumerate(zip(ids[:WRITE_POTS], xy))])
    rng = np.random.default_rng(3)

    def entry(k: int, pest: bool) -> dict:
        return {"id": ids[k], "status": "inspected", "tag_read": k,
                "flower": {"color": "red", "blooms": int(rng.integers(0, 4)), "bug": pest, "confidence": 0.9},
                "images": [f"{ids[k]}_front.jpg", f"{ids[k]}_wrist.jpg"]}

    thread_ms: list[float] = []
    for run in range(WRITE_PRIOR + 1):
        r = start_recording(history, m, "mirte", None, tmp / f"run{run}" / "report.json")
        r.timer = time.perf_counter
        pests = rng.random(WRITE_POTS) < 0.05
        for k, pot in enumerate(m.pots):
            e, kinds = entry(k, bool(pests[k])), ["bug"] if pests[k] else []
            t = time.perf_counter()
            r.recorded(pot, e, kinds)
            if run == WRITE_PRIOR:
                thread_ms.append((time.perf_counter() - t) * 1000)
                r.drain()  # pots are tens of seconds apart on the robot: one transaction each
        r.finished({"outcome": "completed", "sim_time_s": 1.0, "distance_m": 1.0, "pots": []})
        r.wait()
    return thread_ms, [s * 1000 for s in r.write_s], len(r.errors)


@benchmark("history.write")
def bench_write(config: LupinConfig) -> Sample:
    figures: dict = {"pots": WRITE_POTS, "earlier_patrols": WRITE_PRIOR, "goal_ms": 2}
    with tempfile.TemporaryDirectory() as tmp:
        h = open_history(str(Path(tmp) / "h.db"))
        thread_ms, commit_ms, errors = _patrol_cost(h, Path(tmp))
        h.close()
        figures["sqlite"] = {"thread_ms": _stats(thread_ms), "commit_ms": _stats(commit_ms), "write_errors": errors}
    try:
        from lupin.bench.pg_server import PostgresServer

        server = PostgresServer(fsync=True)
    except Exception as exc:  # a failure is a result
        figures["postgresql"] = {"error": str(exc)}
    else:
        try:
            with tempfile.TemporaryDirectory() as tmp:
                h = open_history(server.new_database())
                pg_thread, pg_commit, errors = _patrol_cost(h, Path(tmp))
                h.close()
                figures["postgresql"] = {"thread_ms": _stats(pg_thread), "commit_ms": _stats(pg_commit),
                                         "write_errors": errors}
        finally:
            server.stop()
    figures["load_avg_1m"] = round(os.getloadavg()[0], 2)
    return Sample(thread_ms, figures)




OUTAGE_WORLD_ENV = "LUPIN_BENCH_OUTAGE_WORLD"
"""A world file for ``history.outage`` (``default`` for the built-in 12-pot greenhouse); unset,
the 180-pot two-bay world of ``patrol.large`` (issue 29 asks for a 180-pot patrol)."""


def _outage_world():
    from lupin.bench.patrol import large_world
    from sim.world import load_default_world, load_world

    chosen = os.environ.get(OUTAGE_WORLD_ENV)
    if chosen is None:
        return large_world()
    return load_default_world() if chosen == "default" else load_world(Path(chosen))


def _recorded_patrol(world, config: LupinConfig, tmp: Path, name: str, down_s: float | None) -> tuple[dict, object, Path]:
    """One whole sim patrol recorded in a fresh SQLite history with a spool; with ``down_s``,
    the ``history_down`` event from t=0 for that many seconds of robot time. (report, history
    reopened for judging, spool path)."""
    from mission.history.spool import open_spool
    from mission.jobs.patrol import run_to_end
    from mission.jobs.sim_patrol import start_sim_patrol
    from mission.patrol.events_file import HistoryDown
    from mission.patrol.mission_file import mission_from_world

    (tmp / name).mkdir()
    spool = open_spool(tmp / name)
    h = open_history(str(tmp / name / "h.db"), spool=spool)
    events = [] if down_s is None else [HistoryDown(at=0.0, do="history_down", duration=down_s)]
    run = start_sim_patrol(world, mission_from_world(world), config, tmp / name / "report.json", time.perf_counter,
                           events, history=h)
    recorder = run.history
    doc = run_to_end(run)
    figures = {"spooled_rows": h.outbox.delivered + spool.rows(h.shown), "delivered_rows": h.outbox.delivered,
               "waiting_after": spool.count(h.shown), "write_errors": len(recorder.errors)}
    h.close()
    return doc, figures, tmp / name / "h.db"


@benchmark("history.outage")
def bench_outage(config: LupinConfig) -> Sample:
    """A patrol with the history down for its first half against the same patrol with it up:
    rows spooled and delivered, duplicates and rows lost (judged on the database against the
    report, goal 0), and the robot time of both (goal equal: the robot never waits)."""
    world = _outage_world()
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        up, _, _ = _recorded_patrol(world, config, Path(tmp), "up", None)
        up_wall = time.perf_counter() - t0
        half = up["sim_time_s"] / 2
        t0 = time.perf_counter()
        down, fig, db = _recorded_patrol(world, config, Path(tmp), "down", half)
        down_wall = time.perf_counter() - t0
        h = open_history(str(db), create=False)
        recorded = h.patrols()
        patrol = recorded[0]
        rows = h.observations(patrol.id)
        with h.reading() as c:
            all_rows = c.exec_driver_sql("SELECT count(*) FROM observations").scalar()
        h.close()
    reported = [p["id"] for p in down["pots"]]
    stored = [o.pot_id for o in rows]
    return Sample([up_wall * 1000, down_wall * 1000], {
        "world": world.name, "pots": len(world.pots), "down_s": round(half, 1), **fig,
        "rows_in_database": all_rows, "patrols_in_database": len(recorded),
        "duplicates": len(recorded) - 1 + all_rows - len(set(stored)), "lost": len(set(reported) - set(stored)),
        "in_order": [o.seq for o in rows] == sorted(o.seq for o in rows),
        "outcome": down["outcome"], "robot_time_up_s": up["sim_time_s"], "robot_time_down_s": down["sim_time_s"],
        "robot_time_equal": up["sim_time_s"] == down["sim_time_s"], "ended_recorded": patrol.ended_at is not None,
        "load_avg_1m": round(os.getloadavg()[0], 2)})
