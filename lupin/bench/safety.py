"""Safety benchmarks: the collision monitor's cost, and patrols among people.

``safety.collision_monitor``: one scan's cost in the monitor (its returns into the base frame,
then the stop, slowdown and approach verdict on a twist), on real MuJoCo scans of the built-in
greenhouse taken at poses along the aisles, with a person standing in the aisle ahead in half
of them, for forward, sideways and turning twists: median and p95 per scan (goal <= 0.5 ms).

``safety.people``: whole patrols of generated greenhouses (4 rows x 5 pots, four aisles) with ``WALKERS``
people walking the aisles, seed after seed, until at least ``MIN_ENCOUNTERS`` encounters (a
stretch of the monitor stopping or slowing the base, the report's ``people``) have been
counted; every patrol counts. Judged on ground truth (``mission.jobs.people_log``): contacts
(goal 0) and the least body-to-body clearance to any walker (goal >= 0.2 m); the time lost per
encounter (median, p95: the withheld share of the commanded speed, integrated); patrol success
(every pot inspected and read right, as ``patrol.generated`` judges; goal 1.0); and each
patrol's robot time (the empty greenhouse's is ``patrol.generated``'s).
"""
from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

from hw.collision_monitor import CollisionMonitor
from hw.interfaces import Twist
from lupin.bench import Sample, benchmark
from lupin.bench.patrol import correct_pots
from mission.jobs.people_log import PeopleLog
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig
from sim.backend import SimRobot
from sim.generate import generate_world
from sim.world import Walker, World, load_default_world

POSES = [(x, y, yaw) for x in (2.5, 3.5, 4.5) for y, yaw in ((0.5, 0.0), (2.5, math.pi))]
TWISTS = [Twist(0.4, 0.0, 0.0), Twist(0.0, 0.3, 0.0), Twist(0.3, 0.1, 0.6), Twist(0.1, 0.0, 0.0)]
REPEATS = 50

WALKERS = 3
MIN_ENCOUNTERS = 100
MAX_WORLDS = 40
"""Seeds tried at most (a run that cannot reach MIN_ENCOUNTERS says so rather than running on)."""
ROWS, PER_ROW = 4, 5


@benchmark("safety.collision_monitor")
def collision_monitor(config: LupinConfig) -> Sample:
    world = load_default_world()
    scans = []
    for k, (x, y, yaw) in enumerate(POSES):
        ahead = (x + 0.6 * math.cos(yaw), y + 0.6 * math.sin(yaw))
        walkers = [Walker(id="W1", path=[list(ahead), [ahead[0] + 0.01, ahead[1]]], speed=0.2, start=1e9)] if k % 2 else []
        w = world.model_copy(update={"walkers": walkers, "spawn": world.spawn.model_copy(update={"x": x, "y": y, "yaw": yaw})})
        sim = SimRobot(w, config.sim, config.hw)
        sim.engine.advance_to(0.25)
        scans.append(sim.lidar.latest_scan())
        sim.close()
    monitor = CollisionMonitor(config.hw.collision_monitor, None, config.nav.costmap.robot_radius,
                               config.nav.navigator.lidar_mount)
    times, actions = [], {}
    for _ in range(REPEATS):
        for scan in scans:
            for twist in TWISTS:
                t0 = time.perf_counter()
                monitor.take_scan(scan)
                verdict = monitor.judge(twist)
                times.append((time.perf_counter() - t0) * 1000.0)
                actions[verdict.action] = actions.get(verdict.action, 0) + 1
    return Sample(times, {"scans": len(scans), "twists": len(TWISTS), "points_per_scan": int(np.mean(
        [np.isfinite(s.ranges).sum() for s in scans])), "verdicts": {k: v // REPEATS for k, v in actions.items()}})


def _patrol(world: World, config: LupinConfig) -> tuple[dict, PeopleLog]:
    with tempfile.TemporaryDirectory() as tmp:
        run = start_sim_patrol(world, mission_from_world(world), config, Path(tmp) / "report.json", time.perf_counter)
        people = PeopleLog(run.sim.sim).attach()
        try:
            while not run.done:
                run.step()
            return run.finish(run.outcome()), people
        finally:
            run.close()


@benchmark("safety.people")
def people(config: LupinConfig) -> Sample:
    encounters, lost, clearances, robot_time = [], [], [], []
    contacts = patrols = correct = pots = 0
    failed = []
    for seed in range(1, MAX_WORLDS + 1):
        if len(encounters) >= MIN_ENCOUNTERS:
            break
        world = generate_world(ROWS, PER_ROW, seed, walkers=WALKERS)
        doc, log = _patrol(world, config)
        patrols += 1
        found = doc.get("people", [])
        encounters += found
        lost += [e["lost_s"] for e in found]
        clearances.append(log.clearance)
        contacts += len(log.contacts.onsets)
        right = correct_pots(world, doc)
        correct, pots = correct + right, pots + len(world.pots)
        if right < len(world.pots) or doc["outcome"] != "completed":
            failed.append({"seed": seed, "outcome": doc["outcome"], "correct": right, "pots": len(world.pots)})
        robot_time.append(doc["sim_time_s"])
    lost_arr = np.asarray(lost) if lost else np.zeros(1)
    return Sample([1000.0 * x for x in lost], {
        "encounters": len(encounters), "patrols": patrols, "walkers_per_world": WALKERS,
        "contacts": contacts, "min_clearance_m": round(float(min(clearances)), 3),
        "median_clearance_m": round(float(np.median(clearances)), 3),
        "lost_per_encounter_median_s": round(float(np.median(lost_arr)), 2),
        "lost_per_encounter_p95_s": round(float(np.percentile(lost_arr, 95)), 2),
        "patrol_time_median_s": round(float(np.median(robot_time)), 1),
        "patrol_time_p95_s": round(float(np.percentile(robot_time, 95)), 1),
        "success_rate": round(correct / pots, 4) if pots else 0.0, "patrols_not_all_correct": failed})
