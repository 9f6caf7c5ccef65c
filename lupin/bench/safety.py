"""Safety benchmarks: the collision monitor's cost, and patrols among people.

``safety.collision_monitor``: one scan's cost in the monitor (its returns into the base frame,
then the stop, slowdown and approach verdict on a twist), on real MuJoCo scans of the built-in
greenhouse taken at poses along the aisles, with a person standing in the aisle ahead in half
of them, for forward, sideways and turning twists: median and p95 per scan (goal <= 0.5 ms).

``safety.people``: whole patrols of generated greenhouses (two bays of 6 rows x 4 pots, 14 x 7 m)
with ``WALKERS`` people in the mix ``lupin sim generate --walkers`` makes (sim.generate.ROLES: a
third do not yield and cross the aisles' mouths, cart pushers, a worker standing and one
crouching by the east wall), seed after seed,
until at least ``LUPIN_BENCH_PEOPLE_ENCOUNTERS`` (default ``MIN_ENCOUNTERS``) person encounters
have been counted, and at least ``MIN_PATROLS`` patrols (a quick look: as few as bring its
encounters); every patrol counts. The worlds are
held out (``eval_seeds``): the people rules were traced and mended on world seeds
``TRACED_SEEDS``, whose patrols the code's docstrings cite, so a figure on them would score the
rules on the patrols they were fitted to. An encounter is a walker within 1.0 m of the robot's
body on ground truth (``mission.jobs.people_log``), not a collision-monitor hold: issue 28
found the holds for pots and walls counted as people. Judged on ground truth: contacts while
the robot moves under its own drive (goal 0; ``contacts_standing_or_moving`` counts every touch,
a walker who does not yield walking into a robot standing still included); the least
body-to-body clearance while it moves (goal >= 0.25 m) and the 5th percentile of each
encounter's; the time lost per encounter (median, p95: the collision monitor's withheld share of
the commanded speed, integrated over the encounter); patrol success (every pot inspected and
read right, as ``patrol.generated`` judges; goal >= 0.98); and each patrol's robot time beside
the same world's without walkers. So that a figure can be followed back to what made it, the
``CLOSEST`` nearest passes while moving come with their seed, walker, kind, sim time and the
robot's place, each patrol not all correct with its pots and why, and each patrol's own figures
(``patrols_each``): a patrol runs 15-50 minutes of robot time among people who pace for ever,
and one mishap early on (a cart that does not yield carrying the robot off, its map then a metre
out) decides the rest of it, so the spread between patrols is part of the figure.
"""
from __future__ import annotations

import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from hw.collision_monitor import NONE, CollisionMonitor
from hw.errors import InputError
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

WALKERS = 6
"""One turn of ``sim.generate.ROLES`` (so a third do not yield) in two bays: a person in every
second aisle or cross aisle, one per 16 m^2. Until stop 37 the bench put six in one bay, a person
in every aisle of a 7 x 7 m house (one per 8 m^2, each pacing it for ever): the aisles' pots
then measured the crowd, not the robot (issue 28's closing notes)."""
MIN_ENCOUNTERS = 200
"""Person encounters to count, unless ``ENCOUNTERS_ENV`` says otherwise (a quick look: 30)."""
ENCOUNTERS_ENV = "LUPIN_BENCH_PEOPLE_ENCOUNTERS"
MIN_PATROLS = 3
"""Patrols counted at least, however soon the encounters are in: one patrol's luck is not a rate
(stop 51: the first patrol brought 224 encounters, and the second's ten contacts went uncounted)."""
MAX_WORLDS = 100
"""Seeds tried at most (a run that cannot reach the count says so rather than running on)."""
TRACED_SEEDS = (1, 2, 3, 4, 101, 102, 103, 104, 105, 106, 107, 108, 109, 110, 111, 113, 114, 115)
"""World seeds whose patrols the people rules were traced and mended on (module docstring): 101-103
were the held-out worlds until stop 53 traced their least passes (a cart turning round beside a
waiting robot) to mend them, so from then on the figure is on the next seeds; 105 at stop 54,
104 and 107 at stop 55 (a shove SLAM lost the robot in, a way home down a pacer's aisle); 109
at stop 57 (a worker standing since the first map, ``mission.runtime.stood_at_start``); 106 at stop
59 (a shove SLAM followed at 29-55 % of each scan fitted and drew the map a metre out,
``nav.slam.lidar_odometry.FIT``); 108, 110 and 111 at stop 60 (a step away from a cart's middle
towards its corner, ``hw.people_guard``; a pot given up after one later go beside a pacer,
``patrol.later_goes``); 113 at stop 61 (a robot held still for 2,400 s between a standing
worker and a cart that waited for it, ``hw.people_guard``'s ``escape`` and ``ring_closing``); 115
at stop 62 (a worker who walked up to the robot's front, their legs hidden by the tracker's 0.25 m
self-filter circle, ``mission.runtime.people.People.on_robot``); 114 at stop 64 (two pacers turning at
the bay divider's north end, the one short way between the bays, ``nav.turning_places``)."""
ROWS, PER_ROW, BAYS = 6, 4, 2
CLOSEST = 5
"""The nearest passes while moving listed with where and when they happened."""


@benchmark("safety.collision_monitor")
def collision_monitor(config: LupinConfig) -> Sample:
    world = load_default_world()
    scans = []
    for k, (x, y, yaw) in enumerate(POSES):
        ahead = (x + 0.6 * math.cos(yaw), y + 0.6 * math.sin(yaw))
        walkers = [Walker(id="W1", path=[list(ahead)])] if k % 2 else []  # a worker standing there
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
        monitor = run.robot.monitor
        people = PeopleLog(run.sim.sim, config.arm.kinematics,
                           lambda: 0.0 if monitor.verdict.action == NONE else 1.0 - monitor.verdict.scale,
                           run.robot.base.driving).attach()
        try:
            while not run.done:
                run.step()
            return run.finish(run.outcome()), people
        finally:
            run.close()


def _kind(walker: Walker) -> str:
    """What a walker is, in the words of ``sim.generate.ROLES``."""
    if len(walker.path) == 1:
        return walker.posture
    return "cart" if walker.pushes_cart else "walking"


def _passes(seed: int, world: World, log: PeopleLog) -> list[dict]:
    """Each encounter met while moving: how near, who (seed, walker, kind), when and where."""
    walkers = {w.id: w for w in world.walkers}
    out = []
    for e in log.encounters:
        if e["moving_at"] is None:
            continue
        t, x, y = e["moving_at"]
        w = walkers[e["walker"]]
        out.append({"clearance_m": round(e["nearest_moving_m"], 3), "seed": seed, "walker": w.id, "kind": _kind(w),
                    "yields": w.yields, "t_s": round(t, 2), "robot_xy": [round(x, 2), round(y, 2)]})
    return out


def _wrong(world: World, doc: dict) -> list[dict]:
    """The report's pots not judged right, with their status and why (its failures; an inspected
    pot read wrong; a pot skipped, not visited)."""
    def why(p: dict) -> str:
        return "; ".join(p.get("failures", {}).values()) or ("read wrong" if p["status"] == "inspected" else "not visited")
    return [{"pot": p["id"], "status": p["status"], "why": why(p)}
            for p in doc["pots"] if not correct_pots(world, {"pots": [p]})]


def eval_seeds(seed: int) -> list[int]:
    """The held-out world seeds of a run with sim seed ``seed``, in the order they are patrolled."""
    first = 100 * (seed + 1) + 1
    return [s for s in range(first, first + MAX_WORLDS + len(TRACED_SEEDS)) if s not in TRACED_SEEDS][:MAX_WORLDS]


def _metres(x: float) -> float | None:
    """A clearance for the JSON: to the millimetre, None for none (inf: no pass while moving)."""
    return None if math.isinf(x) else round(float(x), 3)


def _each(seed: int, world: World, doc: dict, log: PeopleLog, right: int, empty_s: float) -> dict:
    """One patrol's own figures (the run's are summed and taken from these)."""
    return {"seed": seed, "encounters": len(log.encounters), "contacts_while_moving": len(log.moving_contacts),
            "contacts_standing_or_moving": len(log.contacts.onsets), "min_clearance_while_moving_m": _metres(log.clearance),
            "correct": right, "pots": len(world.pots), "outcome": doc["outcome"],
            "robot_time_s": doc["sim_time_s"], "empty_robot_time_s": empty_s}


def _wanted() -> tuple[int, int]:
    """Encounters and patrols to count: the figure's, or a quick look's (``ENCOUNTERS_ENV``:
    that many encounters, from as few patrols as bring them)."""
    text = os.environ.get(ENCOUNTERS_ENV)
    if text is None:
        return MIN_ENCOUNTERS, MIN_PATROLS
    if not text.isdigit() or int(text) < 1:
        raise InputError(f"{ENCOUNTERS_ENV}: must be a whole number of encounters, 1 or more (got {text!r})")
    return int(text), 1


def _pct(values: list[float], q: float) -> float | None:
    return round(float(np.percentile(values, q)), 3) if values else None


@benchmark("safety.people")
def people(config: LupinConfig) -> Sample:
    wanted, least_patrols = _wanted()
    met, failed, passes, each = [], [], [], []
    for seed in eval_seeds(config.sim.seed):
        if len(met) >= wanted and len(each) >= least_patrols:
            break
        world = generate_world(ROWS, PER_ROW, seed, bays=BAYS, walkers=WALKERS)
        doc, log = _patrol(world, config)
        met += log.encounters
        passes += _passes(seed, world, log)
        right = correct_pots(world, doc)
        if right < len(world.pots) or doc["outcome"] != "completed":
            failed.append({"seed": seed, "outcome": doc["outcome"], "correct": right, "pots": len(world.pots),
                           "wrong": _wrong(world, doc)})
        empty = _patrol(world.model_copy(update={"walkers": []}), config)[0]["sim_time_s"]
        each.append(_each(seed, world, doc, log, right, empty))
    nearest = [e["nearest_moving_m"] for e in met if e["nearest_moving_m"] is not None]
    lost = [e["lost_s"] for e in met]
    robot_time, empty_time = [e["robot_time_s"] for e in each], [e["empty_robot_time_s"] for e in each]
    extra = [a - b for a, b in zip(robot_time, empty_time)]
    least = [e["min_clearance_while_moving_m"] for e in each if e["min_clearance_while_moving_m"] is not None]
    pots = sum(e["pots"] for e in each)
    return Sample([], {
        "encounters": len(met), "encounters_wanted": wanted, "patrols": len(each), "min_patrols": least_patrols,
        "traced_seeds": list(TRACED_SEEDS), "walkers_per_world": WALKERS,
        "not_yielding_per_world": sum(not w.yields for w in generate_world(ROWS, PER_ROW, 1, bays=BAYS, walkers=WALKERS).walkers),
        "contacts_while_moving": sum(e["contacts_while_moving"] for e in each),
        "contacts_standing_or_moving": sum(e["contacts_standing_or_moving"] for e in each),
        "min_clearance_while_moving_m": min(least, default=None),
        "clearance_p5_m": _pct(nearest, 5), "encounters_met_moving": len(nearest),
        "lost_per_encounter_median_s": _pct(lost, 50), "lost_per_encounter_p95_s": _pct(lost, 95),
        "success_rate": round(sum(e["correct"] for e in each) / pots, 4) if pots else 0.0,
        "patrol_time_median_s": _pct(robot_time, 50), "patrol_time_p95_s": _pct(robot_time, 95),
        "empty_patrol_time_median_s": _pct(empty_time, 50),
        "extra_time_per_patrol_median_s": _pct(extra, 50), "extra_time_per_patrol_p95_s": _pct(extra, 95),
        "closest_while_moving": sorted(passes, key=lambda p: p["clearance_m"])[:CLOSEST],
        "patrols_not_all_correct": failed, "patrols_each": each})
