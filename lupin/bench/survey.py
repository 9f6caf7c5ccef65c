"""Survey benchmarks: a greenhouse with no mission, its pots found by their tags, judged against
the world file (which the survey itself never reads: it only builds the sim).

``survey.default``: the built-in greenhouse. ``survey.generated``: generated greenhouses (seeds
1..5, 3 rows x 5 pots) and a two-bay one (2 bays x 4 rows x 8 pots, a divider wall with
doorways). For each: pots found (a world pot whose tag the mission carries), tag ids right (every
mission pot's tag is a world pot's, placed within ``MATCH`` of it), position error (mission pot
against the world pot of its tag, in the map frame: median and max), facing error (max), robot
time and distance (and per pot), wall time.

``patrol.surveyed``: survey, then patrol what it found on the same robot (``lupin patrol
--survey``), in generated greenhouses (seeds 1..5); a world pot is right when the patrol
inspected the mission pot carrying its tag and read its tag, flower colour and pest as the world
file has them (``patrol.generated``'s rule).
"""
from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

from hw.odometry import Pose2D
from lupin.bench import Sample, benchmark
from lupin.bench.moved_judge import true_poses
from mission.jobs.patrol import run_to_end as patrol_to_end
from mission.jobs.sim_patrol import start_sim_patrol
from mission.jobs.sim_survey import start_sim_survey
from mission.jobs.survey import run_to_end
from mission.patrol.mission_file import Mission
from mission.runtime.config import LupinConfig
from sim.generate import generate_world
from sim.world import World, load_default_world

SEEDS = range(1, 6)
ROWS, PER_ROW = 3, 5
BAYS = (2, 4, 8)
"""bays, rows, pots per row of ``survey.generated``'s two-bay greenhouse."""
MATCH = 0.3
"""A mission pot within this of the world pot carrying its tag counts as that pot, m."""


def _in_map(world: World) -> dict[int, Pose2D]:
    """The world's pots by tag, in the map frame (the dock at the origin)."""
    poses = true_poses(world)
    return {p.tag: poses[p.id] for p in world.pots if p.tag is not None}


def judge_survey(world: World, mission: Mission) -> dict:
    truth = _in_map(world)
    xy, yaw, right = [], [], 0
    for p in mission.pots:
        t = truth.get(p.tag)
        if t is None:
            continue
        d = math.hypot(p.x - t.x, p.y - t.y)
        xy.append(d)
        yaw.append(abs(math.remainder(p.facing - t.yaw, 2 * math.pi)))
        right += d <= MATCH
    return {"world_pots": len(truth), "found": len({p.tag for p in mission.pots} & set(truth)),
            "mission_pots": len(mission.pots), "ids_right": right, "xy": xy, "yaw": yaw}


def survey_once(world: World, config: LupinConfig, patrol: bool = False) -> dict:
    """One survey (and the patrol of what it found); what was found, judged, and what it cost."""
    t0 = time.perf_counter()
    run, sim_run = start_sim_survey(world, config)
    try:
        run_to_end(run)
        mission = run.mission(f"{world.name}-survey")
        out = {**judge_survey(world, mission), "robot_s": run.now - run.t0, "distance_m": run.robot.base.odometry.distance,
               "wall_s": time.perf_counter() - t0, "ended": run.reason or "complete"}
        if patrol and mission.pots:
            with tempfile.TemporaryDirectory() as tmp:
                doc = patrol_to_end(start_sim_patrol(world, mission, run.config, Path(tmp) / "r.json", time.perf_counter,
                                                     sim_run=sim_run))
            out["patrol_right"] = _right_by_tag(world, doc)
    finally:
        run.close()
    return out


def _right_by_tag(world: World, doc: dict) -> int:
    """World pots the patrol got right, matched by the tag its mission pot carries."""
    truth = {p.tag: p for p in world.pots}
    return sum(1 for p in doc["pots"] if p["status"] == "inspected" and p["tag_read"] == p["tag_expected"]
               and p["tag_read"] in truth and (p["flower"] or {}).get("color") == truth[p["tag_read"]].flower
               and (p["flower"] or {}).get("bug") == truth[p["tag_read"]].bug)


def _figures(runs: list[dict]) -> dict:
    xy = np.array([d for r in runs for d in r["xy"]])
    yaw = np.array([d for r in runs for d in r["yaw"]])
    pots = sum(r["world_pots"] for r in runs)
    found = sum(r["found"] for r in runs)
    robot, dist = sum(r["robot_s"] for r in runs), sum(r["distance_m"] for r in runs)
    return {"worlds": len(runs), "pots": pots, "found": found, "found_rate": round(found / pots, 4),
            "ids_right": sum(r["ids_right"] for r in runs),
            "ids_right_rate": round(sum(r["ids_right"] for r in runs) / max(sum(r["mission_pots"] for r in runs), 1), 4),
            "xy_error_median_m": round(float(np.median(xy)), 4) if len(xy) else None,
            "xy_error_max_m": round(float(xy.max()), 4) if len(xy) else None,
            "facing_error_max_rad": round(float(yaw.max()), 4) if len(yaw) else None,
            "robot_time_s": round(robot, 1), "robot_s_per_pot": round(robot / max(found, 1), 2),
            "distance_m": round(dist, 1), "distance_m_per_pot": round(dist / max(found, 1), 2),
            "wall_time_s": round(sum(r["wall_s"] for r in runs), 1), "ended": sorted({r["ended"] for r in runs})}


@benchmark("survey.default")
def survey_default(config: LupinConfig) -> Sample:
    run = survey_once(load_default_world(), config)
    return Sample([run["wall_s"] * 1000.0], _figures([run]))


@benchmark("survey.generated")
def survey_generated(config: LupinConfig) -> Sample:
    small = [survey_once(generate_world(ROWS, PER_ROW, seed), config) for seed in SEEDS]
    bays, rows, per_row = BAYS
    big = survey_once(generate_world(rows, per_row, 1, bays=bays), config)
    return Sample([r["wall_s"] * 1000.0 for r in small + [big]],
                  {**_figures(small + [big]), "generated": _figures(small), "two_bays": _figures([big])})


@benchmark("patrol.surveyed")
def patrol_surveyed(config: LupinConfig) -> Sample:
    runs = [survey_once(generate_world(ROWS, PER_ROW, seed), config, patrol=True) for seed in SEEDS]
    pots = sum(r["world_pots"] for r in runs)
    right = sum(r.get("patrol_right", 0) for r in runs)
    return Sample([r["wall_s"] * 1000.0 for r in runs], {
        "pots": pots, "correct": right, "success_rate": round(right / pots, 4), "survey": _figures(runs)})
