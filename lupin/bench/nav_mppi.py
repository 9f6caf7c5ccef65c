"""The MPPI cycle on a realistic greenhouse costmap: 2000 x 56, all eight critics.

The local costmap is the real one: a 3 x 3 m window around the robot in the built-in
greenhouse's south aisle, marked from a MuJoCo lidar scan and inflated with the seed's values;
the plan runs along the aisle. ``fraction_of_period`` is the median over the 50 ms control
period. The controller is warmed up to its steady state first (60 cycles: the warm-started
sequence reaches 20 path points, so PathAlign scores). Far from the goal the path critics run and
the goal critics are off; ``near_goal_median_ms`` is the same cycle 1 m from the goal, where
the goal critics run instead (Nav2's thresholds make the two sets exclusive: no cycle runs all
eight). ``critic_ms`` is each critic's median in the far case (what to optimise next), with the
shared furthest-reached path index (computed once per cycle) on its own line.
``numpy_rollout_ms`` times the rollout (the one sequential step) as a numpy loop over the 56
steps, beside ``numba_rollout_ms``: the figure that justifies numba.
"""
from __future__ import annotations

import math

import numpy as np

from lupin.bench import Sample, benchmark, time_ms
from mission.runtime.config import LupinConfig
from nav.costmap.layered import local_costmap
from nav.mppi.controller import MppiController
from nav.mppi.critic_data import CriticData
from sim.backend import SimRobot
from sim.world import load_default_world

CYCLES = 200
WARMUP = 60
POSE = (3.0, 0.5, 0.0)
FAR_GOAL = (5.5, 0.5, -math.pi / 2)  # 2.5 m down the aisle: path critics on, goal critics off
NEAR_GOAL = (4.0, 0.5, -math.pi / 2)  # 1 m: goal critics on, PathFollow off


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
    grid = costmap.grid
    v0 = (0.3, 0.0, 0.0)

    def controller_for(goal):
        xs = np.arange(POSE[0], goal[0] + 0.025, 0.05)
        path = np.column_stack([xs, np.full_like(xs, POSE[1]), np.full_like(xs, goal[2])])  # as the Omni model sees it
        ctrl = MppiController(cfg.mppi, cfg.costmap)
        cycle = lambda: ctrl.compute(POSE, v0, path, goal, grid)  # noqa: E731
        for _ in range(WARMUP):
            cycle()  # numba loads its cache; the warm-started sequence reaches its steady state
        return ctrl, cycle, path

    ctrl, cycle, path = controller_for(FAR_GOAL)
    times = time_ms(cycle, CYCLES, warmup=0)
    opt = ctrl.optimizer
    def critic_data():
        return CriticData(np.asarray(POSE, np.float32), opt._v, opt._traj, path, np.asarray(FAR_GOAL, np.float32),
                          grid, cfg.mppi.model_dt, np.zeros(cfg.mppi.batch_size, np.float32))

    data = critic_data()
    critic_ms = {name: round(float(np.median(time_ms(lambda c=critic: c.score(data), 50, warmup=1))), 3)
                 for name, critic in zip(cfg.mppi.critics, opt.critics)}
    critic_ms["furthest_reached"] = round(float(np.median(time_ms(lambda: critic_data().furthest_reached, 50))), 3)
    cv = opt.u.T[:, None, :] + opt._noise
    v = np.asarray(v0, np.float32)
    numba_ms = time_ms(lambda: opt.model.rollout(cv, v, POSE, opt._v, opt._traj), 50, warmup=0)
    numpy_ms = time_ms(lambda: _numpy_rollout(opt.model, cv, v, POSE), 20, warmup=0)
    _, near_cycle, _ = controller_for(NEAR_GOAL)
    near_ms = time_ms(near_cycle, CYCLES // 2, warmup=0)
    median = float(np.median(times))
    return Sample(times, {
        "batch": cfg.mppi.batch_size, "time_steps": cfg.mppi.time_steps, "critics": len(cfg.mppi.critics),
        "fraction_of_period": round(median / (1000.0 / cfg.mppi.frequency), 3),
        "near_goal_median_ms": round(float(np.median(near_ms)), 3),
        "critic_ms": critic_ms,
        "numba_rollout_ms": round(float(np.median(numba_ms)), 3),
        "numpy_rollout_ms": round(float(np.median(numpy_ms)), 3),
    })
