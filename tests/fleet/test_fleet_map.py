"""The map and docks the dispatcher splits on, from a world file (fleet/fleet_map.py,
fleet/fleet_patrol.py): the plan in the first dock's frame, pots and walls where the world has
them, each robot's dock in that frame, and the split it gives two robots of the 3 x 4 greenhouse."""
from __future__ import annotations

import math

import numpy as np
import pytest

from fleet.assign import assign
from fleet.fleet_map import cost_grid, plan_of_world
from fleet.fleet_patrol import world_docks
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig
from sim.generate import generate_world


def _at(m, x, y) -> int:
    ix, iy = m.geometry.cell_of(np.array([x]), np.array([y]))
    return int(m.occupancy[iy[0], ix[0]])


def test_the_plan_is_the_world_seen_from_the_first_dock_and_the_docks_are_in_that_frame():
    world = generate_world(3, 4, 1, robots=2)
    first = world.spawn_poses[0]
    plan = plan_of_world(world, (first.x, first.y, first.yaw))
    for p in world.pots:  # every pot's centre blocked, the approach pose 0.5 m out free
        x, y = p.x - first.x, p.y - first.y
        assert _at(plan, x, y) == 100
        assert _at(plan, x + 0.5 * math.cos(p.facing), y + 0.5 * math.sin(p.facing)) == 0
    assert _at(plan, -first.x - 0.1, 0.0) == 100 and _at(plan, world.floor.x - first.x + 0.1, 0.0) == 100  # walls
    docks = world_docks(world)
    assert docks["r1"] == pytest.approx((0.0, 0.0, 0.0)) and docks["r2"] == pytest.approx((0.0, 1.0, 0.0))
    # a first dock looking north: the world's east is the plan's -y
    turned = plan_of_world(world, (first.x, first.y, math.pi / 2))
    pot = world.pots[0]
    assert _at(turned, pot.y - first.y, -(pot.x - first.x)) == 100


def test_two_robots_get_every_pot_of_the_greenhouse_once_split_on_the_plan():
    world = generate_world(3, 4, 1, robots=2)
    first = world.spawn_poses[0]
    plan = plan_of_world(world, (first.x, first.y, first.yaw))
    mission = mission_from_world(world)
    a = assign(mission, cost_grid(plan, LupinConfig().nav.costmap), world_docks(world), occupancy=plan)
    ids = sorted(p.id for m in a.missions.values() for p in m.pots)
    assert set(a.missions) == {"r1", "r2"} and ids == sorted(p.id for p in mission.pots)
    assert np.isfinite(a.split.makespan) and a.split.makespan < 0.8 * (a.split.cost("r1") + a.split.cost("r2"))
