"""The MPPI cycle on a realistic greenhouse costmap: 2000 x 56, warm and cold.

Which critics run: all eight are *called* in every cycle, but each gates itself on the goal
distance or the path (Nav2's thresholds), so no cycle *scores* with all eight. Measured with the
default config (``critics_scoring`` in the JSON lists, per case, the critics that added cost in
a cycle of that case (a critic with nothing to add, obstacles on a free map, is not listed), so
a config change shows there):

- far, warm (the headline figures, 2.5 m from the goal): constraint, obstacles, path_align,
  path_follow, path_angle, prefer_forward; goal and goal_angle are off (1.4 m threshold);
- near, warm (``near_goal_*``, 1 m from the goal): constraint, obstacles, goal, goal_angle,
  path_angle, prefer_forward; path_follow is off (1.4 m threshold) and so is path_align (the
  trajectories reach about 17 of the 1 m plan's 21 points, short of its 20);
- far, cold (``cold_*``): as far and warm but without path_align (a zero control sequence's
  trajectories do not reach 20 path points).

The local costmap is the real one: a 3 x 3 m window around the robot in the built-in
greenhouse's south aisle, marked from a MuJoCo lidar scan and inflated with the seed's values;
the plan runs along the aisle. ``fraction_of_period`` is the median over the 50 ms control
period.

- **Warm** (the headline median / p95): the controller is run to its steady state first (60
  cycles: the warm-started sequence reaches 20 path points, so PathAlign scores), then 200
  cycles are timed. ``near_goal_median_ms`` is the same 1 m from the goal.
- **Cold** (``cold_median_ms``, ``cold_p95_ms`` over ``cold_starts``): the first cycle of a
  fresh controller (zero control sequence, no history) far from the goal, as after a new goal,
  a cancel or a recovery; numba's compiled code is already loaded (the process's first cycle
  ever also loads numba's cache, a start-up cost, not a cycle's). The controller's
  construction (drawing the noise) is not timed.

``critic_ms`` is each critic's median in the far case (what to optimise next), with the
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
COLD_STARTS = 30
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


class _Watched:
    """A critic that notes whether its ``score`` added any cost."""

    def __init__(self, critic, name: str, seen: set[str]):
        self.critic, self.name, self.seen = critic, name, seen

    def score(self, data) -> None:
        before = data.costs.copy()
        self.critic.score(data)
        if not np.array_equal(before, data.costs):
            self.seen.add(self.name)


def scoring_critics(ctrl: MppiController, cycle) -> list[str]:
    """Run one more ``cycle`` (untimed) with every critic watched; the names of those that added
    cost in it, in the configured order."""
    opt = ctrl.optimizer
    names = list(opt.config.critics)
    seen: set[str] = set()
    original = opt.critics
    opt.critics = [_Watched(c, n, seen) for c, n in zip(original, names)]
    try:
        cycle()
    finally:
        opt.critics = original
    return [n for n in names if n in seen]


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
    scoring = {"far_warm": scoring_critics(ctrl, cycle)}
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
    near_ctrl, near_cycle, _ = controller_for(NEAR_GOAL)
    near_ms = time_ms(near_cycle, CYCLES // 2, warmup=0)
    scoring["near_warm"] = scoring_critics(near_ctrl, near_cycle)
    far_path = path
    cold_ms = []
    for _ in range(COLD_STARTS):
        fresh = MppiController(cfg.mppi, cfg.costmap)
        cold_ms += time_ms(lambda c=fresh: c.compute(POSE, v0, far_path, FAR_GOAL, grid), 1, warmup=0)
    fresh = MppiController(cfg.mppi, cfg.costmap)
    scoring["far_cold"] = scoring_critics(fresh, lambda: fresh.compute(POSE, v0, far_path, FAR_GOAL, grid))
    median = float(np.median(times))
    return Sample(times, {
        "batch": cfg.mppi.batch_size, "time_steps": cfg.mppi.time_steps, "critics": len(cfg.mppi.critics),
        "critics_scoring": scoring,
        "fraction_of_period": round(median / (1000.0 / cfg.mppi.frequency), 3),
        "near_goal_median_ms": round(float(np.median(near_ms)), 3),
        "near_goal_p95_ms": round(float(np.percentile(near_ms, 95)), 3),
        "cold_starts": COLD_STARTS,
        "cold_median_ms": round(float(np.median(cold_ms)), 3),
        "cold_p95_ms": round(float(np.percentile(cold_ms, 95)), 3),
        "critic_ms": critic_ms,
        "numba_rollout_ms": round(float(np.median(numba_ms)), 3),
        "numpy_rollout_ms": round(float(np.median(numpy_ms)), 3),
    })
