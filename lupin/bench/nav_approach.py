"""The navigation acceptance trial as a benchmark: 50 pot approaches in generated greenhouses."""
from __future__ import annotations

import time

import numpy as np

from mission.jobs.approach_trials import run_world
from lupin.bench import Sample, benchmark
from mission.runtime.config import LupinConfig

WORLDS, POTS_PER_WORLD = 10, 5


@benchmark("nav.approach")
def approaches(config: LupinConfig) -> Sample:
    """Times are wall ms per approach; the figures are what the issue asks for: successes,
    median sim time to goal, the worst final yaw error, and how often yaw was the miss."""
    results, times = [], []
    for seed in range(1, WORLDS + 1):
        t0 = time.perf_counter()
        batch = run_world(config, seed, POTS_PER_WORLD)
        per = (time.perf_counter() - t0) * 1000.0 / len(batch)
        times += [per] * len(batch)
        results += batch
    ok = [r for r in results if r.outcome == "succeeded"]
    yaw_misses = [r for r in results if r.outcome != "succeeded" and r.map_error[0] <= 0.25]
    return Sample(times, {
        "approaches": len(results),
        "succeeded": len(ok),
        "median_time_to_goal_s": round(float(np.median([r.sim_time_s for r in ok])), 2) if ok else None,
        "worst_yaw_error_rad": round(max(r.map_error[1] for r in ok), 4) if ok else None,
        "worst_truth_xy_m": round(max(r.truth_error[0] for r in ok), 4) if ok else None,
        "worst_truth_yaw_rad": round(max(r.truth_error[1] for r in ok), 4) if ok else None,
        "yaw_tolerance_misses": len(yaw_misses),
        "bumps": sum(r.bumped for r in results),
        "failures": [f"{r.world_seed}/{r.pot}: {r.reason}" for r in results if r.outcome != "succeeded"],
    })
