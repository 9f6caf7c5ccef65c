"""``safety.blind``: a lidar that goes blind (scans on time, every return invalid) or drops out
(no scans) while the base drives, and how soon the base stops.

The simulated robot drives back and forth across an empty walled floor under the operator's
``manual`` source at ``SPEED``; once the wheels' odometry says it drives at 0.3 m/s or more, the
fault is injected at a random control-tick phase (``TRIALS`` per kind, alternating kinds and
directions). Judged per trial: base ticks from the injection until the twist the base controller
hands the wheels has no linear part (goal for blind: 1, the tick the first blind revolution
arrives on; a dropout waits ``scan_timeout``), and the true distance the base moved from the
injection until it stood (ground truth, the sim's). ``median_ms``/``p95_ms``: the blind
trials' runtime from injection to zero linear twist (ticks x 100 ms); ticks and distances per
kind in the figures. ``false_blind``: blind verdicts over an empty-greenhouse patrol of the
built-in world and of a generated two-bay world (goal 0: an honest scan is never blind).
"""
from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

from hw.collision_monitor import LIDAR_BLIND
from hw.interfaces import Twist
from lupin.bench import Sample, benchmark
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig
from mission.runtime.sim_runtime import start_sim_runtime
from sim.generate import generate_world
from sim.world import Floor, Pose2, World, load_default_world

SPEED = 0.35
"""Commanded speed, m/s: above the 0.3 m/s the figure asks for."""
TRIALS = 30
"""Per kind (blind, dropout)."""
FAULT_S = 1.5
"""How long each injected fault lasts, s (the base stops long before)."""


def _trial_floor() -> World:
    return World(name="blind-bench", floor=Floor(x=8.0, y=6.0), spawn=Pose2(x=4.0, y=3.0, yaw=0.0), pots=[])


def _stops(config: LupinConfig) -> dict[str, list[tuple[int, float]]]:
    rt = start_sim_runtime(_trial_floor(), config)
    robot, sim, sched = rt.robot, rt.sim, rt.robot.scheduler
    rng = np.random.default_rng(config.sim.seed)
    period = 1.0 / config.hw.base.control_rate
    out: dict[str, list[tuple[int, float]]] = {"lidar_blind": [], "lidar_dropout": []}
    try:
        t = 1.0
        sched.run_until(t)
        for k in range(2 * TRIALS):
            kind = "lidar_blind" if k % 2 == 0 else "lidar_dropout"
            twist = Twist(SPEED if (k // 2) % 2 == 0 else -SPEED, 0.0, 0.0)
            while math.hypot(robot.base.odometry.twist.vx, robot.base.odometry.twist.vy) < 0.3:
                robot.mux.publish("manual", twist, t)
                t += period
                sched.run_until(t)
            t += float(rng.uniform(0.0, period))  # at some phase of the control tick
            robot.mux.publish("manual", twist, t)
            sched.run_until(t)
            start, ticks = sim.truth(), None
            getattr(sim.faults, kind)(FAULT_S)
            t0 = t
            moved = [start]
            for n in range(1, round(FAULT_S / period)):  # while the fault lasts
                t = t0 + n * period
                robot.mux.publish("manual", twist, t)
                sched.run_until(t)
                moved.append(sim.truth())
                c = robot.base.command
                if ticks is None and c.vx == 0.0 and c.vy == 0.0:
                    ticks = n
            xy = np.array([(p.x, p.y) for p in moved])
            out[kind].append((ticks if ticks is not None else 99, float(np.hypot(*(xy[-1] - xy[0])))))
            t += FAULT_S + 0.5  # the fault ends and the scans are trusted again before the next
            sched.run_until(t)
    finally:
        rt.close()
    return out


def _false_blind(config: LupinConfig) -> dict[str, int]:
    counts = {}
    for name, world in (("default", load_default_world()), ("two_bay", generate_world(4, 5, 2, bays=2))):
        blind = [0]
        with tempfile.TemporaryDirectory() as tmp:
            run = start_sim_patrol(world, mission_from_world(world), config, Path(tmp) / "report.json", time.perf_counter)
            monitor = run.robot.monitor
            run.robot.scheduler.every("bench.blind", 10.0, lambda now: blind.__setitem__(0, blind[0] + (monitor.fault == LIDAR_BLIND)))
            try:
                while not run.done:
                    run.step()
                counts[name] = blind[0]
                counts[f"{name}_outcome"] = run.finish(run.outcome())["outcome"]
            finally:
                run.close()
    return counts


@benchmark("safety.blind")
def blind(config: LupinConfig) -> Sample:
    stops = _stops(config)
    ticks = [n for n, _ in stops["lidar_blind"]]
    extra = {"speed_mps": SPEED, "trials_per_kind": TRIALS}
    for kind, rows in stops.items():
        n = np.array([r[0] for r in rows], dtype=float)
        d = np.array([r[1] for r in rows])
        extra[kind] = {"ticks_to_zero_median": float(np.median(n)), "ticks_to_zero_p95": float(np.percentile(n, 95)),
                       "ticks_to_zero_max": int(n.max()), "distance_after_median_m": round(float(np.median(d)), 3),
                       "distance_after_p95_m": round(float(np.percentile(d, 95)), 3)}
    extra["false_blind_verdicts"] = _false_blind(config)
    period_ms = 1000.0 / config.hw.base.control_rate
    return Sample([n * period_ms for n in ticks], extra)
