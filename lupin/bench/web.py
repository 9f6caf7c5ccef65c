"""Web dashboard benchmark (issue 32): ``web.pages``, each page's time on a year of history and
in a browser.

- **Server time**, per page, on ``history.query``'s synthetic year (1,460 patrols x 2,000 pots,
  ~2.9 M observations; ``lupin.bench.history``: SQLite cached at ``LUPIN_BENCH_HISTORY_YEAR``,
  PostgreSQL 15 built on a throwaway server): ``lupin web``'s app served by uvicorn on loopback,
  each page asked ``REQUESTS`` times over HTTP, each time of a different pot, patrol or page of
  the list (the greenhouse, always about the latest patrol, over a different number of patrols),
  from the request to the last byte, and the process's CPU time for it (``cpu_ms``: what it
  costs whatever else the machine runs). Median and p95 per page and database; goal <= 300 ms
  (spec/web.md). The benchmark's median and p95 are every page's on SQLite.
- **Load time in headless Chromium** (``lupin.bench.chromium``), per page: navigation start to
  the end of the load event (``PerformanceNavigationTiming.loadEventEnd``), pictures and the
  stylesheet included, on the default history: two whole sim patrols of the default greenhouse,
  the first with P04's pest taken out (so it is new in the second), recorded as ``lupin patrol``
  records them. ``LOADS`` navigations each; the first is cold.

Every request's status is checked (a page that fails counts, ``errors``), and the machine's
1-minute load average is given: on a shared 2-core machine every wall figure is its load's.
"""
from __future__ import annotations

import os
import random
import socket
import tempfile
import threading
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from lupin.bench import Sample, benchmark
from lupin.bench.history import _grid, _stats, on_postgres_year, sqlite_year
from mission.history.store import History, open_history
from mission.runtime.config import LupinConfig

REQUESTS, LOADS = 20, 5
GOAL_MS = 300
PAGES = ("greenhouse", "pot", "patrols", "patrol", "alerts", "greenhouse_json")


@contextmanager
def serving(history: History, runs: Path | None = None):
    """``lupin web``'s app (open: no sign-in) under uvicorn on a free loopback port, the heap
    frozen as ``lupin web`` freezes it; its URL."""
    import uvicorn

    from web.app import freeze_heap, make_app
    from web.auth import Sessions

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = uvicorn.Server(uvicorn.Config(make_app(history, runs, Sessions(None)), host="127.0.0.1", port=port,
                                           log_level="warning", access_log=False))
    freeze_heap()  # as lupin web does
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    until = time.monotonic() + 30
    while not server.started:
        if time.monotonic() > until or not thread.is_alive():
            raise RuntimeError("lupin web's server did not start")
        time.sleep(0.02)
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(10)


def _urls(pick: random.Random, pots: list[str], patrol_ids: list[int], pages: int) -> dict[str, str]:
    """One URL per page, each of a different pot, patrol or list page than the last."""
    return {"greenhouse": f"/?last={pick.choice((5, 10, 15, 20, 30))}", "pot": f"/pots/{pick.choice(pots)}",
            "patrols": f"/patrols?page={pick.randrange(pages)}", "patrol": f"/patrols/{pick.choice(patrol_ids)}",
            "alerts": "/alerts", "greenhouse_json": f"/api/greenhouse?last={pick.choice((5, 10, 15, 20, 30))}"}


def _get(url: str) -> tuple[float, float, int]:
    """(wall ms, this process's CPU ms: the server's work and the client's, status)."""
    t, c = time.perf_counter(), time.process_time()
    try:
        with urllib.request.urlopen(url, timeout=60) as r:
            r.read()
            status = r.status
    except urllib.error.HTTPError as exc:
        status = exc.code
    return (time.perf_counter() - t) * 1000, (time.process_time() - c) * 1000, status


def server_times(url: str, n: int = REQUESTS) -> dict:
    """Each page's time over the synthetic year: ``n`` requests a page after a warm-up one."""
    h = open_history(url, create=False)
    with h.reading() as c:
        patrol_ids = [p for (p,) in c.exec_driver_sql("SELECT id FROM patrols ORDER BY id").all()]
    pots, _ = _grid()
    pick = random.Random(7)
    times: dict[str, list[float]] = {p: [] for p in PAGES}
    cpu: dict[str, list[float]] = {p: [] for p in PAGES}
    errors = 0
    with serving(h) as base:
        for page, path in _urls(pick, pots, patrol_ids, max(1, len(patrol_ids) // 50)).items():
            errors += _get(base + path)[2] != 200  # warm-up: templates compiled, caches filled
        for _ in range(n):
            for page, path in _urls(pick, pots, patrol_ids, max(1, len(patrol_ids) // 50)).items():
                ms, cpu_ms, status = _get(base + path)
                times[page].append(ms)
                cpu[page].append(cpu_ms)
                errors += status != 200
    h.close()
    worst = max(float(np.percentile(v, 95)) for v in times.values())
    return {**{f"{p}_ms": _stats(v) for p, v in times.items()}, "cpu_ms": {p: _stats(v) for p, v in cpu.items()},
            "errors": errors, "p95_worst_ms": round(worst, 1), "all_within_goal": bool(worst <= GOAL_MS and not errors),
            "_times": [t for v in times.values() for t in v]}


def default_history(root: Path, config: LupinConfig) -> tuple[History, dict]:
    """Two whole sim patrols of the default greenhouse in a new SQLite history under ``root``,
    the first with P04's pest taken out: what a grower sees after a pest appeared."""
    from mission.jobs.patrol import run_to_end
    from mission.jobs.sim_patrol import start_sim_patrol
    from mission.patrol.mission_file import mission_from_world
    from sim.world import load_default_world

    world = load_default_world()
    clean = world.model_copy(update={"pots": [p.model_copy(update={"bug": False}) for p in world.pots]})
    h = open_history(str(root / "history.db"))
    outcomes = []
    for k, w in enumerate((clean, world)):
        run = start_sim_patrol(w, mission_from_world(w), config, root / f"patrol-{k}" / "report.json",
                               time.perf_counter, history=h)
        outcomes.append(run_to_end(run)["outcome"])
    return h, {"patrols": outcomes, "pots": len(world.pots)}


def browser_times(history: History, n: int = LOADS) -> dict:
    """Each page's load in headless Chromium, ``n`` navigations a page (the first cold)."""
    from lupin.bench.chromium import Chromium

    latest = history.patrols(limit=1)[0]
    pot = history.observations(latest.id)[0].pot_id
    paths = {"greenhouse": "/", "pot": f"/pots/{pot}", "patrols": "/patrols", "patrol": f"/patrols/{latest.id}",
             "alerts": "/alerts"}
    times: dict[str, list[float]] = {p: [] for p in paths}
    with serving(history) as base, Chromium() as b:
        for _ in range(n):
            for page, path in paths.items():
                times[page].append(b.goto(base + path))
        foreign = [u for u in b.requested() if not u.startswith(base + "/")]
    return {**{f"{p}_ms": _stats(v) for p, v in times.items()}, "cold_ms": {p: round(v[0], 1) for p, v in times.items()},
            "requests_elsewhere": len(foreign)}


@benchmark("web.pages")
def bench_pages(config: LupinConfig) -> Sample:
    figures: dict = {"goal_ms": GOAL_MS, "requests_per_page": REQUESTS}
    with tempfile.TemporaryDirectory() as tmp:
        path, build_s = sqlite_year(Path(tmp))
        figures["sqlite"] = {**server_times(str(path)), "build_s": build_s}
    times = figures["sqlite"].pop("_times")
    figures["postgresql"] = on_postgres_year(server_times)
    figures["postgresql"].pop("_times", None)
    with tempfile.TemporaryDirectory() as tmp:
        try:
            h, made = default_history(Path(tmp), config)
            figures["browser"] = {**made, **browser_times(h)}
            h.close()
        except Exception as exc:  # no chromium: said, not hidden
            figures["browser"] = {"error": f"{type(exc).__name__}: {exc}"}
    figures["all_within_goal"] = all(figures[db].get("all_within_goal", False) for db in ("sqlite", "postgresql"))
    figures["load_avg_1m"] = round(os.getloadavg()[0], 2)
    return Sample(times, figures)
