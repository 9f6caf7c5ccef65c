"""Turning places closed to the planner (nav/turning_places.py): with a way round, the plan takes
it; a turning place holding the robot or the goal stays open; with no way round, nothing is
closed and the navigator plans through (seeds 114 and 115's bay divider, in miniature)."""
from __future__ import annotations

import numpy as np
import pytest

from nav.config import PlannerConfig
from nav.costmap.grid import FREE, LETHAL, CostGrid
from nav.planner import NavfnPlanner, PlanningError
from nav.turning_places import close_turns

RES = 0.05
ROBOT = 0.22


def divided(gaps: tuple[str, ...] = ("north", "south")) -> CostGrid:
    """A 10 x 7 m floor split by a divider at x = 5 m, with a 1.2 m way round its north end
    (y 5.8-7) and one round its south end (y 0-1.2), each when asked for."""
    data = np.full((140, 200), FREE, np.uint8)
    data[:, 98:102] = LETHAL
    if "north" in gaps:
        data[116:, 98:102] = FREE
    if "south" in gaps:
        data[:24, 98:102] = FREE
    return CostGrid(data, RES, 0.0, 0.0)


NORTH_TURN = (6.0, 6.4, 0.9)
"""Where a cart pusher pacing the cross aisle east of the divider turns: at its north end."""


def plan(grid: CostGrid, start=(3.0, 5.0), goal=(7.0, 5.0)) -> np.ndarray:
    return NavfnPlanner(PlannerConfig()).plan(grid, start, goal)


def test_with_a_way_round_the_plan_keeps_out_of_the_turning_place():
    grid = divided()
    assert plan(grid)[:, 1].max() > 5.8  # the short way, round the north end
    closed = close_turns(grid, [NORTH_TURN], ROBOT, [(3.0, 5.0), (7.0, 5.0)])
    path = plan(closed)
    assert path[:, 1].min() < 1.2  # the long way, round the south end
    assert np.hypot(path[:, 0] - 6.0, path[:, 1] - 6.4).min() > NORTH_TURN[2] + ROBOT


def test_a_turning_place_holding_the_robot_or_the_goal_stays_open():
    grid = divided()
    assert close_turns(grid, [NORTH_TURN], ROBOT, [(3.0, 5.0), (6.3, 6.0)]) is None  # the goal in it
    assert close_turns(grid, [NORTH_TURN], ROBOT, [(5.8, 6.5), (3.0, 1.0)]) is None  # the robot in it
    assert close_turns(grid, [], ROBOT, [(3.0, 5.0)]) is None


def test_with_no_way_round_the_closed_grid_has_no_plan():
    """What ``Navigator._plan_round_turns`` falls back from: the grid as it was plans through."""
    grid = divided(("north",))
    closed = close_turns(grid, [NORTH_TURN], ROBOT, [(3.0, 5.0), (7.0, 5.0)])
    with pytest.raises(PlanningError):
        plan(closed)
    assert plan(grid)[:, 1].max() > 5.8
