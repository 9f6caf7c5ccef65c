"""Scenario benchmark: the scenario suite (``tests/scenarios/*.yaml``) as CI runs it.

``scenario.suite`` runs every scenario in two worker processes (this machine's two cores, as
``pytest -n 2`` does) and reports how many there are and passed, the suite's wall time, the
per-scenario wall times (median / p95), and the e-stop figures over every press: the worst
number of control ticks from the press to all-zero wheel duty, the greatest true distance the
robot travelled after a press (the coast) with its speed at the press, and the slowest true
speed any press found the robot at (a press at rest tests nothing). Then each judged event's
effect per scenario (``mission.scenario.effects``) and the events that never fired.
"""
from __future__ import annotations

import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from lupin.bench import Sample, benchmark
from mission.runtime.config import LupinConfig

SUITE = Path(__file__).resolve().parents[2] / "tests" / "scenarios"
WORKERS = 2


def _run(path: str) -> dict:
    from fleet.scenario_runner import run_any
    from mission.scenario.scenario_file import load_scenario

    with tempfile.TemporaryDirectory() as tmp:
        return run_any(load_scenario(path), Path(tmp)).as_json()


@benchmark("scenario.suite")
def suite(config: LupinConfig) -> Sample:
    files = sorted(str(p) for p in SUITE.glob("*.yaml"))
    t0 = time.perf_counter()
    with ProcessPoolExecutor(WORKERS) as pool:
        results = list(pool.map(_run, files))
    wall = time.perf_counter() - t0
    presses = [(r["name"], p) for r in results for p in r["estop"]]
    worst = max(presses, key=lambda rp: rp[1]["ticks_to_zero"] or 10**6)
    coast = max(presses, key=lambda rp: rp[1]["distance_after_m"])
    slowest = min(presses, key=lambda rp: rp[1]["speed_mps"])
    events = [(r["name"], e) for r in results for e in r["events"]]
    return Sample([r["wall_time_s"] * 1000.0 for r in results], {
        "scenarios": len(results), "passed": sum(r["passed"] for r in results),
        "failed": [r["name"] for r in results if not r["passed"]],
        "suite_wall_s": round(wall, 1), "workers": WORKERS,
        "estop_presses": len(presses), "estop_worst_ticks": worst[1]["ticks_to_zero"],
        "estop_max_distance_m": coast[1]["distance_after_m"], "estop_max_distance_speed_mps": coast[1]["speed_mps"],
        "estop_max_distance_scenario": coast[0],
        "estop_min_speed_mps": slowest[1]["speed_mps"], "estop_min_speed_scenario": slowest[0],
        "estop": [{"scenario": n, **p} for n, p in presses],
        "events_not_fired": [f"{n}: events[{e['index']}] ({e['do']})" for n, e in events if e["fired"] is None],
        "effects": [{"scenario": n, "do": e["do"], "fired": e["fired"], "speed_mps": e["speed_mps"], **e["effect"]}
                    for n, e in events if e["effect"]]})
