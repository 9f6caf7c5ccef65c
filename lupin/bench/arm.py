"""Arm benchmarks: camera-aiming IK, and the servo bus traffic of the dead-band write loop."""
from __future__ import annotations

import math
import time

import numpy as np

from arm import limits
from arm.aim import AimResult, CameraAim, bloom_can_be_at
from arm.config import IkConfig, KinematicsConfig
from arm.kinematics import miss_distance, planar
from lupin.bench import Sample, benchmark
from lupin.bench.ik_targets import EXPECTED, target_classes
from mission.runtime.config import LupinConfig
from mission.runtime.sim_runtime import start_sim_runtime
from sim.world import Floor, Pose2, World

IK_TARGETS = 200
"""Reachable targets (the figure compared across runs: success_rate, median, p95)."""
IK_EDGE_TARGETS = 20
"""Targets of each other class (``lupin.bench.ik_targets``)."""
HOLD_S = 30.0
MOVES = ("inspect", "pick", "place", "tuck", "home", "inspect", "zero", "home")


def judge(target: np.ndarray, result: AimResult, k: KinematicsConfig, c: IkConfig) -> str:
    """How a solve was answered, checked here and not taken from the solver: ``solved`` (the
    pose is inside the windows, its optical axis passes within tolerance of a target where a
    bloom can be, in range, from above), ``refused`` (not ok, with a reason), ``unclear`` (not
    ok, no reason) or ``wrong`` (claims ok but one of those checks fails)."""
    if not result.ok:
        return "refused" if result.reason.strip() else "unclear"
    q = result.q
    if q is None or np.shape(q) != (4,) or not limits.within(q, tol=1e-6) or not bloom_can_be_at(target, c):
        return "wrong"
    miss, along = miss_distance(q, target, k)
    _, _, _, dz = planar(q[1], q[2], q[3], k, math)
    if miss > c.tolerance or not (c.min_range - 1e-4 <= along <= c.max_range + 1e-4) \
            or dz > -math.sin(c.min_look_down) + 1e-6:
        return "wrong"
    return "solved"


def tally(answers: dict[str, list[str]], times: dict[str, list[float]], reasons: dict[str, str]) -> dict:
    """Per class: targets, the answer expected, how many got each answer, ms; and the totals:
    ``wrong_answers`` (claimed success and missed), ``failures`` (wrong, unclear, or a
    reachable target refused)."""
    classes, wrong, failures = {}, 0, 0
    for name, got in answers.items():
        counts = {a: got.count(a) for a in ("solved", "refused", "wrong", "unclear")}
        t = np.asarray(times[name])
        classes[name] = {"targets": len(got), "expected": EXPECTED[name], **counts,
                         "as_expected": got.count(EXPECTED[name]),
                         "median_ms": round(float(np.median(t)), 3), "p95_ms": round(float(np.percentile(t, 95)), 3),
                         "example_reason": reasons.get(name, "")}
        wrong += counts["wrong"]
        failures += counts["wrong"] + counts["unclear"] + (counts["refused"] if EXPECTED[name] == "solved" else 0)
    return {"classes": classes, "wrong_answers": wrong, "failures": failures}


@benchmark("arm.ik")
def ik(config: LupinConfig) -> Sample:
    """One camera-aiming solve (casadi + Ipopt, solver built once) per target. Times and
    ``success_rate`` are over the reachable targets (on target within tolerance, inside the
    windows, checked here); ``classes`` reports every class, the unreachable and borderline
    ones too (``lupin.bench.ik_targets``), by the answer each got."""
    k, c = config.arm.kinematics, config.arm.ik
    aim = CameraAim(k, c)
    sets = target_classes(IK_EDGE_TARGETS, config.sim.seed, k, c, reachable=IK_TARGETS)
    answers: dict[str, list[str]] = {}
    times: dict[str, list[float]] = {}
    reasons: dict[str, str] = {}
    for name, targets in sets.items():
        answers[name], times[name] = [], []
        for t in targets:
            t0 = time.perf_counter()
            r = aim.aim(t)
            times[name].append((time.perf_counter() - t0) * 1000.0)
            answers[name].append(judge(t, r, k, c))
            if not r.ok and name not in reasons:
                reasons[name] = r.reason
    reach = answers["reachable"]
    return Sample(times["reachable"], {"success_rate": round(reach.count("solved") / len(reach), 3),
                                       "targets": len(reach), **tally(answers, times, reasons)})


class _CountingBus:
    def __init__(self, bus):
        self.bus, self.moves = bus, 0

    def __getattr__(self, name):
        return getattr(self.bus, name)

    def move(self, servo_id, position, duration_ms):
        self.moves += 1
        self.bus.move(servo_id, position, duration_ms)


@benchmark("arm.bus_writes")
def bus_writes(config: LupinConfig) -> Sample:
    """Bus writes per second of the arm's 10 Hz loop on the sim servos: holding ``inspect``
    (the dead-band's whole point: near zero) and while moving through the presets. Times are
    wall ms of one arm tick (5 position reads + dead-band decisions + writes)."""
    world = World(name="open", floor=Floor(x=6.0, y=6.0), spawn=Pose2(x=3.0, y=3.0, yaw=0.0), pots=[])
    rt = start_sim_runtime(world, config)
    arm, scheduler = rt.robot.arm, rt.robot.scheduler
    bus = _CountingBus(arm.interface.bus)
    arm.interface.bus = arm.stall.bus = bus
    times = []
    tick = arm.tick

    def timed(now):
        t0 = time.perf_counter()
        tick(now)
        times.append((time.perf_counter() - t0) * 1000.0)

    scheduler.cancel("arm")  # the same tick, re-registered with a stopwatch around it
    scheduler.every("arm", config.arm.reassert.rate, timed)
    try:
        scheduler.run_for(0.3)
        arm.preset("inspect")
        scheduler.run_for(4.0)
        n0, t0 = bus.moves, scheduler.clock.now()
        scheduler.run_for(HOLD_S)
        hold = (bus.moves - n0) / (scheduler.clock.now() - t0)
        moving_s, moving_writes = 0.0, 0
        for name in MOVES:
            arm.preset(name)
            n0, t0 = bus.moves, scheduler.clock.now()
            scheduler.run_for(0.2)
            while arm.moving:
                scheduler.run_for(0.1)
            moving_s += scheduler.clock.now() - t0
            moving_writes += bus.moves - n0
            scheduler.run_for(1.0)
    finally:
        rt.close()
    return Sample(times, {"writes_per_s_hold": round(hold, 3),
                          "writes_per_s_moving": round(moving_writes / moving_s, 2),
                          "hold_s": HOLD_S, "moving_s": round(moving_s, 1)})
