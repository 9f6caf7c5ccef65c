"""Simulator benchmarks: real-time factor while driving, and camera render time."""
from __future__ import annotations

import time

import numpy as np

from lupin.bench import Sample, benchmark
from mission.runtime.config import LupinConfig, with_seed
from mission.jobs.drive import start_drive
from sim.backend import SimRobot
from sim.world import load_default_world

RUNS = 7
RUN_SIM_S = 20.0
FRAMES = 30


@benchmark("sim.realtime")
def realtime(config: LupinConfig) -> Sample:
    """Wall ms per simulated second with the robot driving the default tour: physics, the
    10 Hz base control, mux, e-stop, LEDs and a 10 Hz lidar, all on the scheduler.
    One sample per run (model build excluded); rtf = 1000 / ms."""
    world = load_default_world()
    times = []
    for i in range(RUNS):
        run = start_drive(world, with_seed(config, config.sim.seed + i), "tour")
        t0 = time.perf_counter()
        run.robot.scheduler.run_until(RUN_SIM_S)
        times.append((time.perf_counter() - t0) * 1000.0 / RUN_SIM_S)
        run.close()
    rtf = 1000.0 / np.asarray(times)
    return Sample(times, {"rtf_median": round(float(np.median(rtf)), 1),
                          "rtf_p5": round(float(np.percentile(rtf, 5)), 1),
                          "sim_s_per_run": RUN_SIM_S, "physics_dt": config.sim.physics.timestep})


@benchmark("sim.render")
def render(config: LupinConfig) -> Sample:
    """One 640x480 front-camera frame (EGL offscreen, CPU), after a warm-up frame."""
    sim = SimRobot(load_default_world(), config.sim, config.hw)
    cam = sim.hal.cameras["front"]
    cam.capture()
    times = []
    for _ in range(FRAMES):
        t0 = time.perf_counter()
        cam.capture()
        times.append((time.perf_counter() - t0) * 1000.0)
    sim.close()
    return Sample(times, {"width": cam.width, "height": cam.height})
