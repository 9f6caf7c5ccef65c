"""The navigation acceptance trial as a benchmark: 50 pot approaches in generated greenhouses.

Judged on ground truth (``mission.jobs.approach_trials``): ``succeeded`` counts the approaches
whose navigator arrived *and* whose true pose (the sim's, read only to judge) ends within the
goal checker's tolerance of the approach pose, so the pot is inspected from where it should be;
``navigator_succeeded`` is the robot's own count beside it, and ``false_arrivals`` the arrivals
the truth does not bear out. Times are wall ms of each approach alone (the world's start-up
left out), so the median and p95 are over approaches; ``median_time_to_goal_s`` and
``p95_time_to_goal_s`` are sim seconds of the successful ones. ``contacts`` counts every
contact of the chassis with the world (each touch, the same body again too), ``bumps`` the
approaches with at least one.
"""
from __future__ import annotations

import time

import numpy as np

from lupin.bench import Sample, benchmark
from mission.jobs.approach_trials import Approach, run_world
from mission.runtime.config import LupinConfig

WORLDS, POTS_PER_WORLD = 10, 5


def figures(results: list[Approach]) -> dict:
    """The benchmark's figures from its approaches (ground truth decides success)."""
    ok = [r for r in results if r.succeeded]
    sim_s = [r.sim_time_s for r in ok]
    arrived = [r for r in results if r.outcome == "succeeded"]
    yaw_misses = [r for r in results if r.outcome != "succeeded" and r.map_error[0] <= r.tolerance[0]]
    return {
        "approaches": len(results),
        "succeeded": len(ok),
        "judged_on": "ground truth: navigator arrived and the true pose is within tolerance of the approach pose",
        "navigator_succeeded": len(arrived),
        "false_arrivals": sum(not r.truth_within for r in arrived),
        "median_time_to_goal_s": round(float(np.median(sim_s)), 2) if ok else None,
        "p95_time_to_goal_s": round(float(np.percentile(sim_s, 95)), 2) if ok else None,
        "worst_yaw_error_rad": round(max(r.map_error[1] for r in ok), 4) if ok else None,
        "worst_truth_xy_m": round(max(r.truth_error[0] for r in ok), 4) if ok else None,
        "worst_truth_yaw_rad": round(max(r.truth_error[1] for r in ok), 4) if ok else None,
        "yaw_tolerance_misses": len(yaw_misses),
        "bumps": sum(r.bumped for r in results),
        "contacts": sum(r.contacts for r in results),
        "failures": [f"{r.world_seed}/{r.pot}: {_why(r)}" for r in results if not r.succeeded],
    }


def _why(r: Approach) -> str:
    if r.outcome != "succeeded":
        return r.reason or r.outcome
    return (f"navigator arrived but the truth is {r.truth_error[0]:.3f} m / {r.truth_error[1]:.3f} rad "
            f"from the approach pose")


@benchmark("nav.approach")
def approaches(config: LupinConfig) -> Sample:
    """Times are wall ms of each approach; the figures are judged on ground truth."""
    results: list[Approach] = []
    for seed in range(1, WORLDS + 1):
        results += run_world(config, seed, POTS_PER_WORLD, wall=time.perf_counter)
    return Sample([r.wall_s * 1000.0 for r in results], figures(results))
