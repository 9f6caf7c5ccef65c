"""The robots layer (issue 34): another robot of the fleet, where it says it is, is lethal out to
the two footprints and the margin from its centre, falls off beyond; it comes in the map frame
and the local costmap places it through map -> odom; NavFn goes round it, and the grid without
people (what the navigator waits on) has it out of the way; a robot alone has nothing drawn."""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D
from hw.people import Person
from nav.config import NavConfig
from nav.costmap.grid import LETHAL
from nav.costmap.layered import global_costmap, local_costmap
from nav.costmap.robots import Peer, no_peers
from nav.planner import NavfnPlanner

CFG = NavConfig()
R = CFG.costmap.robot_radius
KEEP_OUT = 2 * R + CFG.costmap.robots.margin


def cost(costmap, x, y) -> int:
    return int(costmap.grid.cost_at(np.array([x]), np.array([y]))[0])


def open_floor():
    cm = global_costmap(CFG.costmap)
    cm.set_static(np.zeros((80, 120), np.int8), 0.05, -3.0, -2.0)  # 6 x 4 m of open, explored floor
    return cm


def test_another_robot_is_lethal_to_both_footprints_and_the_margin_then_falls_off():
    cm = open_floor()
    cm.robots.peers = lambda: [Peer("r2", 0.0, 0.0, 0.0)]
    cm.set_static(np.zeros((80, 120), np.int8), 0.05, -3.0, -2.0)  # the layer is read at every rebuild
    assert cost(cm, KEEP_OUT - 0.04, 0.0) == LETHAL
    assert cost(cm, 0.0, -(KEEP_OUT - 0.04)) == LETHAL
    just_past, further = cost(cm, KEEP_OUT + 0.06, 0.0), cost(cm, KEEP_OUT + 0.16, 0.0)
    assert 252 >= just_past > further >= 72
    assert cost(cm, KEEP_OUT + 0.35, 0.0) == 0


def test_a_silent_robot_stands_still_and_is_kept_out_of_by_less():
    cm = open_floor()
    cm.robots.peers = lambda: [Peer("r2", 0.0, 0.0, 0.0, silent=True)]
    cm.set_static(np.zeros((80, 120), np.int8), 0.05, -3.0, -2.0)
    still = 2 * R + CFG.costmap.robots.still_margin
    assert cost(cm, still - 0.04, 0.0) == LETHAL
    assert cost(cm, still + CFG.costmap.robots.still_gradient + 0.06, 0.0) == 0  # room to stand beside it
    assert cost(cm, KEEP_OUT - 0.04, 0.0) < LETHAL  # where one heard from lately is lethal
    cm.robots.peers = lambda: [Peer("r2", 0.0, 0.0, 0.0), Peer("r3", 2.0, 0.0, 0.0, silent=True)]
    cm.set_static(np.zeros((80, 120), np.int8), 0.05, -3.0, -2.0)
    assert cost(cm, KEEP_OUT - 0.04, 0.0) == LETHAL and cost(cm, 2.0 - (still - 0.04), 0.0) == LETHAL


def test_a_robot_alone_has_nothing_drawn_and_a_robot_that_left_the_fleet_neither():
    cm = open_floor()
    alone = cm.grid.data
    assert cm.robots.apply(alone, cm.grid.geometry) is alone  # not even a copy
    cm.robots.peers = lambda: [Peer("r2", 0.0, 0.0, 0.0)]
    cm.set_static(np.zeros((80, 120), np.int8), 0.05, -3.0, -2.0)
    assert cost(cm, 0.0, 0.0) == LETHAL
    cm.robots.peers = no_peers
    cm.set_static(np.zeros((80, 120), np.int8), 0.05, -3.0, -2.0)
    assert np.array_equal(cm.grid.data, alone)


def test_peers_come_in_the_map_frame_and_the_local_costmap_places_them_by_map_to_odom():
    map_to_odom = Pose2D(1.0, 0.0, math.pi / 2)  # odom's origin at map (1, 0), turned a quarter
    cm = local_costmap(CFG.costmap, map_to_odom=lambda: map_to_odom)
    cm.robots.peers = lambda: [Peer("r2", 1.0, 1.0, 0.0)]  # map (1, 1) is odom (1, 0)
    cm.clear()  # rebuilt with the peer
    assert cost(cm, 1.0, 0.0) == LETHAL
    assert cost(cm, 0.0, 1.0) == 0


def test_the_planner_goes_round_a_robot_in_the_way_and_without_people_it_is_gone():
    cm = open_floor()
    cm.robots.peers = lambda: [Peer("r2", 0.0, 0.0, math.pi)]
    cm.set_static(np.zeros((80, 120), np.int8), 0.05, -3.0, -2.0)
    path = NavfnPlanner(CFG.planner).plan(cm.grid, (-2.0, 0.0), (2.0, 0.0))
    assert np.hypot(path[:, 0], path[:, 1]).min() >= KEEP_OUT - 0.05  # never inside its keep-out
    free = cm.without_people()
    assert cost(cm, 0.0, 0.0) == LETHAL and free.cost_at(np.array([0.0]), np.array([0.0]))[0] == 0


def test_a_wait_for_a_track_on_another_robot_says_it_waits_for_a_robot_and_for_a_person_otherwise():
    from tests.nav.test_navigator_people import GOAL, IN_THE_AISLE, START, Rig

    walker = Person(12, START.x + 3.0, START.y, -1.0, 0.0, 0.2, 0.9)  # 3 m ahead, coming at it
    for robot in (False, True):
        lane, aisle = Rig([walker]), Rig([IN_THE_AISLE])
        for rig, track in ((lane, walker), (aisle, IN_THE_AISLE)):  # the track on r2, its pose told 0.6 m off
            rig.glob.robots.peers = (lambda t=track: [Peer("r2", t.x + 0.6, t.y, 0.0)]) if robot else no_peers
            rig.nav.navigate_to(GOAL, 0.0, timeout=8.0)
        lane.run(0.5)
        aisle.run(2.0)
        assert lane.nav.waiting_for == ("out of a robot's way" if robot else "out of a walker's way")
        assert aisle.nav.waiting_for == ("a robot" if robot else "a person") + " in the only way"
