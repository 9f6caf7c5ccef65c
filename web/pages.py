"""What each page of the dashboard shows (spec/web.md), as data: one function per page, each
asking the history through one open connection (``History.reading()``: one consistent view) with
``mission.history.queries``, the questions ``lupin history`` and the console ask.

Each returns a :class:`Page`: ``data`` is the page's JSON twin (``/api/...``: plain JSON types,
times ISO 8601 UTC), ``view`` what only the HTML needs (SVG geometry, the saved map). Every page
is bounded on a year's history (1,460 patrols x 2,000 pots): the greenhouse reads its latest two
patrols, the pest map over the last N and a thinned month of pest counts; a pot its own rows by
the pot's index; the patrol list a page at a time.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from sqlalchemy import Connection

from mission.history import queries
from mission.history.alerts import alerts as find_alerts
from mission.history.changes import patrol_changes
from mission.history.records import Observation, Patrol, iso
from web import charts
from web.reports import read_report, read_text, report_dir, saved_occupancy, served_file

PEST_LAST = 10
"""Patrols the greenhouse's pest pressure is counted over by default (``lupin history pests``)."""
TREND_DAYS, TREND_POINTS = 28, 28
"""The pest trend: the last four weeks, at most one point a day's worth."""
POT_TABLE, POT_PICTURES, POT_LOOK = 60, 8, 30
"""A pot's page lists its newest 60 observations (all of them in its CSV and JSON) and the
pictures of its newest 8 patrols whose pictures are still there, side by side, looking back
over its newest 30 (each a look at the disk)."""
PATROLS_PER_PAGE = 50
LISTED = 200
"""The greenhouse lists the pots to look at (new pests first, then pests by pressure, then
failed pots) up to this many: the map has them all."""

RESULTS = {"ok": "✓", "anomaly": "!", "pest": "✱", "failed": "✕", "skipped": "–", "not seen": "?"}
"""Each result's word and symbol: never colour alone (spec/web.md)."""


@dataclass
class Page:
    data: dict
    """The JSON twin."""
    view: dict = field(default_factory=dict)
    """What only the HTML needs."""


def result(o: Observation | None) -> str:
    """A pot's latest result, a key of :data:`RESULTS`."""
    if o is None:
        return "not seen"
    if o.status != "inspected":
        return "failed" if o.status == "failed" else "skipped"
    if o.bug:
        return "pest"
    return "anomaly" if o.anomalies else "ok"


def image_url(patrol_id: int, path: str | None) -> str | None:
    return None if not path else f"/patrols/{patrol_id}/files/{Path(path).name}"


def _flower(o: Observation) -> str:
    if o.flower_color is None:
        return "-"
    return "no bloom" if o.flower_color == "none" else f"{o.flower_color} x{o.blooms}"


def greenhouse(conn: Connection, runs: Path | None, mission: str | None = None,
               last: int = PEST_LAST) -> Page | None:
    """``/``: the latest patrol of a mission (default: the latest patrolled), its pots by last
    result and pest pressure over the last ``last`` patrols, new pests marked, the trend; None
    when no patrol of ``mission`` is recorded."""
    known = queries.missions(conn)
    if mission is not None and mission not in known:
        return None
    mission = mission or (known[0] if known else None)
    data: dict = {"missions": known, "mission": mission, "last": last, "latest": None, "before": None, "pots": [],
                  "pests_now": 0, "new_pests": [], "trend": [], "alerts": 0}
    if mission is None:
        return Page(data, {"map": None})
    latest = queries.latest_patrols(conn, mission, 1)[0]
    earlier = queries.latest_patrols(conn, mission, 1, before=latest, world=latest.world)
    before = earlier[0] if earlier else None
    now = queries.observations(conn, latest.id)
    prior = queries.observations(conn, before.id) if before else []
    pressure = queries.pest_map(conn, last, mission)
    new = {c.pot for c in patrol_changes({o.pot_id: o for o in prior}, now) if c.kind == "pest_new"}
    by_pot = {o.pot_id: o for o in now}
    pots = []
    for p in pressure.pots:
        o = by_pot.get(p.pot_id)
        pots.append({"pot": p.pot_id, "x": p.x, "y": p.y, "result": result(o), "new_pest": p.pot_id in new,
                     "pests": p.pests, "observed": p.observed, "pressure": round(p.pressure, 4), "streak": p.streak,
                     "flower": _flower(o) if o else "-", "anomalies": list(o.anomalies) if o else []})
    trend = queries.pest_trend(conn, latest, TREND_DAYS, TREND_POINTS)
    data.update(latest=_patrol(latest), before=_patrol(before) if before else None, pots=pots,
                pests_now=sum(1 for o in now if o.bug), new_pests=sorted(new),
                pressure_patrols=len(pressure.patrols),
                trend=[{"patrol": t.id, "started_at": iso(t.started_at), "pests": t.pests} for t in trend],
                alerts=len(find_alerts(now, prior)))
    geometry = charts.greenhouse_map(pots, saved_occupancy(report_dir(latest.report_path, runs)))
    return Page(data, {"map": geometry, "map_patrol": latest.id, "trend": charts.trend_chart(
        [{"started_at": t.started_at, "pests": t.pests} for t in trend]),
        "listed": sorted((p for p in pots if p["new_pest"] or p["result"] in ("pest", "failed")),
                         key=lambda p: (not p["new_pest"], p["result"] != "pest", -p["pressure"], p["pot"]))[:LISTED]})


def pot(conn: Connection, pot_id: str, runs: Path | None, mission: str | None = None) -> Page | None:
    """``/pots/<id>``: one pot over time, in the greenhouse of its latest observation; None when
    the history has no such pot."""
    timeline = queries.pot_timeline(conn, pot_id, mission)
    if not timeline:
        return None
    entries = [e.as_json() for e in timeline]
    newest = entries[::-1]
    shown = []
    for e in timeline[::-1][:POT_LOOK]:
        o = e.observation
        where = report_dir(o.wrist_image or o.front_image, runs)
        wrist, front = (image_url(e.patrol, path) if path and served_file(where, Path(path).name) else None
                        for path in (o.wrist_image, o.front_image))
        if wrist or front:
            shown.append({"patrol": e.patrol, "when": iso(e.started_at), "wrist": wrist, "front": front,
                          "flower": _flower(o), "pest": o.bug})
        if len(shown) == POT_PICTURES:
            break
    chart = charts.pot_chart([{"started_at": e.started_at, "blooms": e.observation.blooms, "bug": e.observation.bug,
                               "status": e.observation.status, "when": iso(e.started_at)} for e in timeline])
    latest = timeline[-1].observation
    data = {"pot": pot_id, "mission": timeline[-1].mission, "world": timeline[-1].world, "observations": len(entries),
            "latest": {"result": result(latest), **newest[0]}, "pictures": shown, "timeline": entries}
    rows = [{**e, "result": result(t.observation), "flower": _flower(t.observation)}
            for e, t in zip(newest[:POT_TABLE], timeline[::-1])]
    return Page(data, {"chart": chart, "rows": rows})


def patrols(conn: Connection, page: int = 0, mission: str | None = None) -> Page:
    """``/patrols``: every patrol, newest first, a page at a time."""
    got = queries.patrols(conn, mission, None, PATROLS_PER_PAGE + 1, page * PATROLS_PER_PAGE)
    return Page({"page": page, "per_page": PATROLS_PER_PAGE, "more": len(got) > PATROLS_PER_PAGE,
                 "patrols": [_patrol(p) for p in got[:PATROLS_PER_PAGE]]})


def patrol(conn: Connection, patrol_id: int, runs: Path | None) -> Page | None:
    """``/patrols/<id>``: one patrol's report: its pots, anomalies, what changed since the one
    before it, run.png and its config."""
    p = queries.patrol(conn, patrol_id)
    if p is None:
        return None
    rows = queries.observations(conn, patrol_id)
    earlier = queries.latest_patrols(conn, p.mission, 1, before=p, world=p.world)
    before = earlier[0] if earlier else None
    changed = queries.changed(conn, before.id, p.id) if before else []
    where = report_dir(p.report_path, runs)
    report = read_report(where)
    if report is not None and isinstance(report.get("anomalies"), list):
        anomalies = [a for a in report["anomalies"] if isinstance(a, dict)]
    else:  # the report is gone: the kinds the history kept
        anomalies = [{"kind": k, "pot": o.pot_id, "detail": ""} for o in rows for k in o.anomalies]
    pests = sum(1 for o in rows if o.bug)
    data = {"patrol": _patrol(p, len(rows), pests), "before": _patrol(before) if before else None,
            "pots": [{**o.as_json(), "result": result(o)} for o in rows], "anomalies": anomalies,
            "changes": [c.as_json() for c in changed], "report": report is not None,
            "run_png": f"/patrols/{p.id}/files/run.png" if served_file(where, "run.png") else None,
            "config": read_text(where, "config.yaml")}
    return Page(data, {"rows": [{**r, "flower": _flower(o)} for r, o in zip(data["pots"], rows)]})


def alerts(conn: Connection, mission: str | None = None) -> Page | None:
    """``/alerts``: what needs a person after the latest patrol of a mission; None when no
    patrol of ``mission`` is recorded."""
    known = queries.missions(conn)
    if mission is not None and mission not in known:
        return None
    mission = mission or (known[0] if known else None)
    data: dict = {"missions": known, "mission": mission, "latest": None, "before": None, "alerts": []}
    if mission is None:
        return Page(data)
    latest = queries.latest_patrols(conn, mission, 1)[0]
    earlier = queries.latest_patrols(conn, mission, 1, before=latest, world=latest.world)
    prior = queries.observations(conn, earlier[0].id) if earlier else []
    found = find_alerts(queries.observations(conn, latest.id), prior)
    data.update(latest=_patrol(latest), before=_patrol(earlier[0]) if earlier else None,
                alerts=[a.as_json() for a in found])
    return Page(data)


def _patrol(p: Patrol, observed: int | None = None, pests: int | None = None) -> dict:
    out = p.as_json()
    if observed is not None:
        out.update(observed=observed, pests=pests)
    out["outcome"] = out["outcome"] or ("running" if p.ended_at is None else None)
    return out
