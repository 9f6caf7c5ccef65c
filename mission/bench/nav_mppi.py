"""The MPPI cycle on a realistic greenhouse costmap: 2000 x 56, all eight critics.

The local costmap is the real one: a 3 x 3 m window around the robot in the built-in
greenhouse's south aisle, marked from a MuJoCo lidar scan and inflated with the seed's values;
the plan runs along the aisle. ``fraction_of_period`` is the median over the 50 ms control
period. ``numpy_rollout_ms`` times the rollout (the one sequential step) as a numpy loop over
the 56 steps, beside ``numba_rollout_ms``: the figure that justifies numba.
"""
from __future__ import annotations

import math

import numpy as np

from mission.bench import Sample, benchmark, time_ms
from mission.runtime.config import LupinConfig
from nav.costmap.layered import local_costmap
from nav.mppi.controller import MppiController
from sim.backend import SimRobot
from sim.world import load_default_world

CYCLES = 200
POSE = (3.0, 0.5, 0.0)


def _numpy_rollout(model, cv, v0, pose):
    """The same rollout as ``nav.mppi.motion_models`` in numpy: vectorised over the batch,
    a Python loop over time (each step depends on the last)."""
    _, b, t = cv.shape
    v = np.empty_like(cv)
    v[:, :, 0] = v0[:, None]
    for i in range(1, t):
        want = np.clip(cv[:, :, i - 1], model.lo[:, None], model.hi[:, None])
        step = (model.acc * model.dt)[:, None]
        v[:, :, i] = np.clip(want, v[:, :, i - 1] - step, v[:, :, i - 1] + step)
    yaw = pose[2] + np.cumsum(v[2] * model.dt, axis=1)
    prev = np.concatenate([np.full((b, 1), pose[2], np.float32), yaw[:, :-1]], axis=1)
    c, s = np.cos(prev), np.sin(prev)
    x = pose[0] + np.cumsum((v[0] * c - v[1] * s) * model.dt, axis=1)
    y = pose[1] + np.cumsum((v[0] * s + v[1] * c) * model.dt, axis=1)
    return v, x, y, yaw


@benchmark("nav.mppi")
def mppi_cycle(config: LupinConfig) -> Sample:
    cfg = config.nav
    sim = SimRobot(load_default_world(), config.sim, config.hw)
    sim.place(*POSE)
    scan = sim.hal.lidar.latest_scan()
    sim.close()
    costmap = local_costmap(cfg.costmap)
    mx, my, _ = cfg.navigator.lidar_mount
    costmap.update(scan, (POSE[0] + mx, POSE[1] + my, POSE[2]), POSE[:2])
    xs = np.arange(POSE[0], POSE[0] + 1.45, 0.05)
    path = np.column_stack([xs, np.full_like(xs, POSE[1]), np.zeros_like(xs)])
    goal = (5.5, 0.5, -math.pi / 2)
    ctrl = MppiController(cfg.mppi, cfg.costmap)

    def cycle():
        ctrl.compute(POSE, (0.3, 0.0, 0.0), path, goal, costmap.grid)

    for _ in range(5):
        cycle()  # warm-up: numba loads its cache, the sequence warms up
    times = time_ms(cycle, CYCLES, warmup=0)
    opt = ctrl.optimizer
    cv = opt.u.T[:, None, :] + opt._noise
    v0 = np.array([0.3, 0.0, 0.0], np.float32)
    numba_ms = time_ms(lambda: opt.model.rollout(cv, v0, POSE, opt._v, opt._traj), 50, warmup=0)
    numpy_ms = time_ms(lambda: _numpy_rollout(opt.model, cv, v0, POSE), 20, warmup=0)
    median = float(np.median(times))
    return Sample(times, {
        "batch": cfg.mppi.batch_size, "time_steps": cfg.mppi.time_steps, "critics": len(cfg.mppi.critics),
        "fraction_of_period": round(median / (1000.0 / cfg.mppi.frequency), 3),
        "numba_rollout_ms": round(float(np.median(numba_ms)), 3),
        "numpy_rollout_ms": round(float(np.median(numpy_ms)), 3),
    })
