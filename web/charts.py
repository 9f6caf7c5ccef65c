"""The dashboard's pictures as SVG geometry, computed on the server: the greenhouse map, a pot's
blooms and pests over time, the pest trend. The templates only write out what is computed here,
so a page needs no chart library and nothing from the internet, and a chart is a few kB of text
whatever the history's size.

The map is drawn in metres (the map frame, y up turned to SVG's y down): the saved SLAM map of
the latest patrol underneath when it is still beside its report, each pot a disc shaded by pest
pressure on ``lupin history pests``' scale (green none, yellow half, red a pest every patrol;
grey never judged), its latest result as a mark a reader tells without colour: a ring for a
pest, a cross for failed, a dashed outline for skipped or not seen, a star and ``NEW`` for a new
pest.
"""
from __future__ import annotations

from datetime import datetime, timedelta
from urllib.parse import quote

import numpy as np

from mission.history.pest_map import nearest_spacing, pressure_colour
from nav.occupancy import OccupancyMap

MARGIN_M = 0.6
POT_R_M = 0.15
"""A pot's disc: 0.15 m, a greenhouse pot's radius, shrunk where pots stand closer."""
CHART_W, CHART_H, PAD_L, PAD_R, PAD_T, PAD_B = 720, 220, 40, 12, 14, 34
TREND_W, TREND_H = 360, 90
LABELLED = 60
"""Up to this many pots each is named on the map; past that the names would be ink over ink
(each pot still names itself on hover and links to its page)."""


def hex_colour(bgr: tuple[int, int, int]) -> str:
    b, g, r = bgr
    return f"#{r:02x}{g:02x}{b:02x}"


FILLS = [hex_colour(pressure_colour(k / 100)) for k in range(101)]
"""The pressure scale in 1 % steps (2,000 pots' colours are then a look-up each)."""


def pressure_fill(pests: int, observed: int) -> str:
    return "#9a9a9a" if not observed else FILLS[round(100 * pests / observed)]


def greenhouse_map(pots: list[dict], occupancy: OccupancyMap | None) -> dict:
    """``pots``: the greenhouse page's (``pot``, ``x``, ``y`` in m or None, ``result``,
    ``new_pest``, ``pests``, ``observed``, ``streak``, ``flower``). The SVG's ``viewBox``, the
    disc radius, the background map's placement and a ``mark`` per placed pot: where, its fill,
    its classes and its tooltip, all computed here so the template only writes them out (its
    filters and tests on 2,000 pots were half the greenhouse page's time)."""
    placed = [p for p in pots if p["x"] is not None and p["y"] is not None]
    xy = np.array([(p["x"], p["y"]) for p in placed], float).reshape(-1, 2)
    r = float(min(POT_R_M, 0.42 * nearest_spacing(xy))) if len(xy) else POT_R_M
    lo = xy.min(axis=0) - MARGIN_M if len(xy) else np.array([-1.0, -1.0])
    hi = xy.max(axis=0) + MARGIN_M if len(xy) else np.array([1.0, 1.0])
    background = None
    if occupancy is not None:
        w, h = occupancy.width * occupancy.resolution, occupancy.height * occupancy.resolution
        background = {"x": round(occupancy.origin_x, 3), "y": round(-(occupancy.origin_y + h), 3),
                      "width": round(w, 3), "height": round(h, 3)}
        lo = np.minimum(lo, (occupancy.origin_x, occupancy.origin_y))
        hi = np.maximum(hi, (occupancy.origin_x + w, occupancy.origin_y + h))
    marks = [{"pot": p["pot"], "href": f"/pots/{quote(p['pot'], safe='')}", "cx": f"{p['x']:.3f}",
              "cy": f"{-p['y']:.3f}", "fill": pressure_fill(p["pests"], p["observed"]),
              "cls": f"pot r-{p['result'].replace(' ', '-')}{' new' if p['new_pest'] else ''}",
              "result": p["result"], "new": p["new_pest"], "title": _tooltip(p)} for p in placed]
    span = hi - lo
    return {"viewbox": f"{lo[0]:.3f} {-hi[1]:.3f} {span[0]:.3f} {span[1]:.3f}", "r": round(r, 3),
            "ring": round(r * 0.3, 3), "font": round(r * 1.1, 3), "background": background, "marks": marks,
            "labelled": len(marks) <= LABELLED}


def _tooltip(p: dict) -> str:
    streak = f", {p['streak']} in a row" if p["streak"] else ""
    return (f"{p['pot']}: {p['result']}{' (NEW pest)' if p['new_pest'] else ''}; pest {p['pests']}/{p['observed']} "
            f"patrols{streak}; {p['flower']}")


def _x_scale(times: list[datetime], width: float, pad_l: float, pad_r: float):
    t0, t1 = times[0].timestamp(), times[-1].timestamp()
    span = max(t1 - t0, 1.0)
    return lambda t: round(pad_l + (t.timestamp() - t0) / span * (width - pad_l - pad_r), 1)


def pot_chart(entries: list[dict]) -> dict | None:
    """Blooms as a line and each pest as a red mark above it, over time; ``entries`` oldest first,
    each with ``started_at`` (datetime), ``blooms`` (int or None) and ``bug`` (bool or None)."""
    if not entries:
        return None
    times = [e["started_at"] for e in entries]
    x = _x_scale(times, CHART_W, PAD_L, PAD_R)
    top = max([e["blooms"] or 0 for e in entries] + [3])
    base = CHART_H - PAD_B
    y = lambda b: round(base - b / top * (base - PAD_T - 12), 1)  # noqa: E731
    line = " ".join(f"{x(e['started_at'])},{y(e['blooms'])}" for e in entries if e["blooms"] is not None)
    pests = [{"x": x(e["started_at"]), "when": e["when"]} for e in entries if e["bug"]]
    failed = [{"x": x(e["started_at"]), "when": e["when"]} for e in entries if e["status"] != "inspected"]
    ticks = [{"y": y(b), "label": str(b)} for b in range(0, top + 1, max(1, top // 4))]
    k = np.linspace(0, len(times) - 1, min(len(times), 5)).round().astype(int)
    picked = list(dict.fromkeys(k.tolist()))
    dates = [{"x": x(times[i]), "label": _day(times[i], times[-1] - times[0]),
              "anchor": "start" if j == 0 else "end" if j == len(picked) - 1 else "middle"}
             for j, i in enumerate(picked)]
    return {"width": CHART_W, "height": CHART_H, "left": PAD_L, "right": CHART_W - PAD_R, "base": base,
            "top": PAD_T, "line": line, "pests": pests, "failed": failed, "ticks": ticks, "dates": dates,
            "pest_y": PAD_T - 2, "points": len(entries)}


def _day(t: datetime, span: timedelta) -> str:
    """A date on an axis: the day, and the time too when the axis spans less than two days."""
    return t.strftime("%d %b %H:%M" if span < timedelta(days=2) else "%d %b")


def trend_chart(points: list[dict]) -> dict | None:
    """Pots with a pest, patrol by patrol (``points`` oldest first: ``started_at``, ``pests``)."""
    if not points:
        return None
    x = _x_scale([p["started_at"] for p in points], TREND_W, 8, 8)
    span = points[-1]["started_at"] - points[0]["started_at"]
    top = max(max(p["pests"] for p in points), 1)
    base = TREND_H - 18
    y = lambda v: round(base - v / top * (base - 8), 1)  # noqa: E731
    return {"width": TREND_W, "height": TREND_H, "base": base, "top": top,
            "line": " ".join(f"{x(p['started_at'])},{y(p['pests'])}" for p in points),
            "last": {"x": x(points[-1]["started_at"]), "y": y(points[-1]["pests"])},
            "from": _day(points[0]["started_at"], span), "to": _day(points[-1]["started_at"], span),
            "right": TREND_W - 8}
