"""Arm benchmarks: camera-aiming IK, and the servo bus traffic of the dead-band write loop."""
from __future__ import annotations

import time

from arm.aim import CameraAim, sample_reachable_targets
from lupin.bench import Sample, benchmark
from mission.runtime.config import LupinConfig
from mission.runtime.sim_runtime import start_sim_runtime
from sim.world import Floor, Pose2, World

IK_TARGETS = 200
HOLD_S = 30.0
MOVES = ("inspect", "pick", "place", "tuck", "home", "inspect", "zero", "home")


@benchmark("arm.ik")
def ik(config: LupinConfig) -> Sample:
    """One camera-aiming solve (casadi + Ipopt, solver built once) per target, over targets
    spread across the reachable set; success = on target within tolerance, inside the windows."""
    aim = CameraAim(config.arm.kinematics, config.arm.ik)
    targets = sample_reachable_targets(IK_TARGETS, config.sim.seed, config.arm.kinematics, config.arm.ik)
    times, ok = [], 0
    for t in targets:
        t0 = time.perf_counter()
        r = aim.aim(t)
        times.append((time.perf_counter() - t0) * 1000.0)
        ok += r.ok
    return Sample(times, {"success_rate": round(ok / len(targets), 3), "targets": len(targets)})


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
