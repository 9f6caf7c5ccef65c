"""``nav.mppi`` says which critics score in the cycles it times, measured and not assumed: the
goal critics are off far from the goal and on near it, and a cold start (a fresh controller's
first cycle) is a different cycle from the warm steady state (PathAlign off)."""
from __future__ import annotations

import math

import numpy as np

from lupin.bench.nav_mppi import scoring_critics
from nav.config import NavConfig
from nav.costmap.config import CostmapsConfig
from nav.mppi.controller import MppiController
from tests.nav.builders import draw_disc, dummy_costmap, straight_path

POSE, V0 = (0.5, 1.5, 0.0), (0.3, 0.0, 0.0)


def _case(goal_x: float, warm: int, obstacle: bool = False):
    cfg = NavConfig().mppi
    grid = dummy_costmap(origin=(0.0, 0.0))
    if obstacle:
        grid = draw_disc(grid, 1.2, 1.9, 0.1)  # beside the path: some trajectories pass near it
    goal = (goal_x, 1.5, -math.pi / 2)
    points = straight_path(POSE[:2], goal[:2])
    path = np.column_stack([points, np.full(len(points), goal[2])])
    ctrl = MppiController(cfg, CostmapsConfig())
    cycle = lambda: ctrl.compute(POSE, V0, path, goal, grid)  # noqa: E731
    for _ in range(warm):
        cycle()
    return scoring_critics(ctrl, cycle), list(cfg.critics)


def test_far_from_the_goal_the_goal_critics_do_not_score_and_path_align_does_when_warm():
    far, names = _case(3.0, warm=60)
    assert len(names) == 8 and len(far) < 8
    assert "goal" not in far and "goal_angle" not in far
    assert {"constraint", "path_align", "path_follow"} <= set(far)
    assert "obstacles" not in far  # a free costmap: called, but nothing to add


def test_an_obstacle_near_the_trajectories_makes_the_obstacle_critic_score():
    far, _ = _case(3.0, warm=60, obstacle=True)
    assert "obstacles" in far


def test_near_the_goal_the_goal_critics_score_and_path_follow_does_not():
    near, _ = _case(1.5, warm=60)
    assert {"goal", "goal_angle"} <= set(near)
    assert "path_follow" not in near


def test_a_cold_cycle_scores_without_path_align():
    cold, _ = _case(3.0, warm=0)
    assert "path_align" not in cold and "path_follow" in cold


def test_watching_leaves_the_critics_as_they_were():
    cfg = NavConfig().mppi
    ctrl = MppiController(cfg, CostmapsConfig())
    before = list(ctrl.optimizer.critics)
    grid = dummy_costmap()
    path = np.column_stack([straight_path(POSE[:2], (2.5, 1.5)), np.zeros(len(straight_path(POSE[:2], (2.5, 1.5))))])
    scoring_critics(ctrl, lambda: ctrl.compute(POSE, V0, path, (2.5, 1.5, 0.0), grid))
    assert ctrl.optimizer.critics == before
