"""Patrol benchmarks: whole patrols in the sim, as `lupin patrol` runs them.

``patrol.default``: the built-in greenhouse, every pot, SLAM, MPPI at 20 Hz and both cameras
rendered, three times: wall time (median) and robot time, the real-time factor and pots per
minute of robot time.
``patrol.no_strafe``: the same patrol with MPPI's differential-drive model (vy = 0): what the
mecanum base's strafe buys, in robot time. ``patrol.generated``: 20 generated greenhouses
(seeds 1..20, 3 rows x 5 pots); a pot counts as correct when it was inspected and the report
carries its tag, its flower colour and its pest flag as the world file has them.
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

from lupin.bench import Sample, benchmark
from mission.jobs.patrol import run_to_end
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world
from sim.world import World, load_default_world

REPEATS = 3
"""Whole patrols per figure: the sim time is the same every run (deterministic for a seed); the
wall time is not, so it is reported as a median (and the p95) of three."""
GENERATED_SEEDS = range(1, 21)
ROWS, PER_ROW = 3, 5


def patrol_once(world: World, config: LupinConfig) -> tuple[dict, float]:
    """One whole patrol of every pot of ``world``; (report, wall seconds)."""
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        run = start_sim_patrol(world, mission_from_world(world), config, Path(tmp) / "report.json", time.perf_counter)
        doc = run_to_end(run)
        return doc, time.perf_counter() - t0


def correct_pots(world: World, doc: dict) -> int:
    truth = {p.id: p for p in world.pots}
    return sum(1 for p in doc["pots"] if p["status"] == "inspected" and p["tag_read"] == truth[p["id"]].tag
               and (p["flower"] or {}).get("color") == truth[p["id"]].flower
               and (p["flower"] or {}).get("bug") == truth[p["id"]].bug)


def repeated(config: LupinConfig) -> Sample:
    """``REPEATS`` patrols of the default greenhouse; figures from the median wall time."""
    runs = [patrol_once(load_default_world(), config) for _ in range(REPEATS)]
    doc, walls = runs[0][0], sorted(w for _, w in runs)
    wall = walls[len(walls) // 2]
    inspected = sum(p["status"] == "inspected" for p in doc["pots"])
    sim = doc["sim_time_s"]
    return Sample([w * 1000.0 for _, w in runs], {
        "outcome": doc["outcome"], "wall_time_s": round(wall, 2), "sim_time_s": round(sim, 2),
        "rtf": round(sim / wall, 2), "pots_per_min": round(inspected / (sim / 60.0), 3),
        "pots": len(doc["pots"]), "inspected": inspected, "distance_m": doc["distance_m"],
        "same_sim_time": len({d["sim_time_s"] for d, _ in runs}) == 1})


@benchmark("patrol.default")
def default(config: LupinConfig) -> Sample:
    return repeated(config)


@benchmark("patrol.no_strafe")
def no_strafe(config: LupinConfig) -> Sample:
    return repeated(with_overrides(config, {"nav": {"mppi": {"motion_model": "diff"}}}))


@benchmark("patrol.generated")
def generated(config: LupinConfig) -> Sample:
    walls, pots, correct, failed = [], 0, 0, []
    for seed in GENERATED_SEEDS:
        world = generate_world(ROWS, PER_ROW, seed)
        doc, wall = patrol_once(world, config)
        walls.append(wall * 1000.0)
        pots += len(world.pots)
        right = correct_pots(world, doc)
        correct += right
        if right < len(world.pots):
            failed.append(seed)
    return Sample(walls, {"pots": pots, "correct": correct, "success_rate": round(correct / pots, 4),
                          "worlds": len(GENERATED_SEEDS), "worlds_not_all_correct": failed})
