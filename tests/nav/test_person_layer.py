"""The person layer (issue 28 item 2): a lethal keep-out round each person (their radius, 0.3 m
of clearance and the robot's radius), the inflation's falloff beyond, a costly stretch ahead of a
walker; people only (pots keep their distances); NavFn goes round by another aisle, and the
grid without people tells a person in the only way from no way at all."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hw.odometry import Pose2D
from hw.people import Person
from nav.config import NavConfig
from nav.costmap.grid import LETHAL, UNKNOWN
from nav.costmap.layered import global_costmap, local_costmap
from nav.planner import NavfnPlanner, PlanningError

CFG = NavConfig()
R = CFG.costmap.robot_radius
STANDING = Person(id=1, x=0.0, y=0.0, vx=0.0, vy=0.0, radius=0.2, confidence=0.9)
KEEP_OUT = 0.2 + 0.3 + R


def cost(costmap, x, y) -> int:
    return int(costmap.grid.cost_at(np.array([x]), np.array([y]))[0])


def test_a_standing_person_is_lethal_to_the_keep_out_then_falls_off_then_nothing():
    cm = local_costmap(CFG.costmap, lambda: [STANDING])
    assert cost(cm, KEEP_OUT - 0.04, 0.0) == LETHAL
    assert cost(cm, 0.0, -(KEEP_OUT - 0.04)) == LETHAL
    just_past = cost(cm, KEEP_OUT + 0.06, 0.0)
    further = cost(cm, KEEP_OUT + 0.16, 0.0)
    assert 252 >= just_past > further >= 72  # the inflation's falloff, as the critic reads it
    assert cost(cm, KEEP_OUT + 0.35, 0.0) == 0


def test_a_walker_keeps_the_robot_out_of_its_next_second_and_nothing_behind():
    walker = Person(id=2, x=0.0, y=0.0, vx=0.0, vy=0.8, radius=0.2, confidence=0.9)
    cm = global_costmap(CFG.costmap, lambda: [walker])
    cm.set_static(np.zeros((120, 120), np.int8), 0.05, -3.0, -3.0)  # open, explored floor
    assert cost(cm, 0.0, KEEP_OUT + 0.7) == LETHAL  # 0.7 m further along its way: inside the 0.8 m stretch
    assert 72 <= cost(cm, 0.0, KEEP_OUT + 0.9) < LETHAL  # past it: the falloff
    assert cost(cm, 0.0, -(KEEP_OUT + 0.5)) == 0  # as far behind it: free


def test_unsure_tracks_and_nobody_change_nothing():
    plain = local_costmap(CFG.costmap).grid.data
    unsure = Person(id=3, x=0.0, y=0.0, vx=0.0, vy=0.0, radius=0.2, confidence=0.2)
    assert np.array_equal(local_costmap(CFG.costmap, lambda: [unsure]).grid.data, plain)
    assert not np.any(plain)


def test_people_come_in_odom_and_the_global_costmap_places_them_by_map_to_odom():
    odom_in_map = Pose2D(1.0, 0.0, math.pi / 2)
    cm = global_costmap(CFG.costmap, lambda: [Person(4, 1.0, 0.0, 0.0, 0.0, 0.2, 0.9)], lambda: odom_in_map)
    cm.cover(-1.0, -1.0, 3.0, 3.0)
    assert cost(cm, 1.0, 1.0) == LETHAL  # odom (1, 0) is map (1, 1)
    assert cost(cm, 1.0 + KEEP_OUT + 0.4, 1.0) == UNKNOWN  # beyond the person: still unexplored


# -- planning round people -----------------------------------------------------------------------

RES = 0.05


def two_aisles() -> np.ndarray:
    """6 x 3.2 m walled floor, a bench x 1.5..4.5, y 1.4..1.8 down the middle: a south aisle
    (y 0.05..1.4) and a north one (y 1.8..3.15), each too narrow to pass a person in it at 0.3 m."""
    w, h = int(6.0 / RES), int(3.2 / RES)
    occ = np.zeros((h, w), dtype=np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    occ[int(1.4 / RES):int(1.8 / RES), int(1.5 / RES):int(4.5 / RES)] = 100
    return occ


def planned(people):
    cm = global_costmap(CFG.costmap, lambda: people)
    cm.set_static(two_aisles(), RES, 0.0, 0.0)
    return cm, NavfnPlanner(CFG.planner)


def test_navfn_goes_round_by_the_other_aisle_when_a_person_stands_in_one():
    cm, planner = planned([Person(5, 3.0, 0.72, 0.0, 0.0, 0.2, 0.9)])
    path = planner.plan(cm.grid, (0.7, 1.6), (5.3, 1.6))
    assert path[:, 1].max() > 1.9  # by the north aisle
    d = np.hypot(path[:, 0] - 3.0, path[:, 1] - 0.72) - 0.2 - R
    assert d.min() >= 0.3  # body to body


def test_with_both_aisles_held_there_is_no_path_but_there_is_one_once_they_step_aside():
    cm, planner = planned([Person(5, 3.0, 0.72, 0.0, 0.0, 0.2, 0.9), Person(6, 3.0, 2.48, 0.0, 0.0, 0.2, 0.9)])
    with pytest.raises(PlanningError):
        planner.plan(cm.grid, (0.7, 1.6), (5.3, 1.6))
    assert len(planner.plan(cm.without_people(), (0.7, 1.6), (5.3, 1.6))) > 50


def test_pots_keep_todays_distances_with_a_person_elsewhere():
    alone, _ = planned([])
    near, _ = planned([Person(5, 3.0, 0.72, 0.0, 0.0, 0.2, 0.9)])
    a, b = alone.grid.data, near.grid.data
    gy, gx = np.mgrid[0:a.shape[0], 0:a.shape[1]]
    cx, cy = near.grid.geometry.centre_of(gx, gy)
    far = np.hypot(cx - 3.0, cy - 0.72) > KEEP_OUT + 0.3
    assert np.array_equal(a[far], b[far])
    assert not np.array_equal(a, b)


def test_a_walker_who_paused_keeps_the_robot_out_of_their_walk_both_ways_in_the_costmaps_frame():
    """Paused at the end of their walk, a cart pusher turns and walks back (safety.people seed 2,
    1,472 s: the robot crossed in front of one and was walked into): their last walk's stretch
    both ways, turned into the global costmap's frame by map -> odom."""
    now = [Person(id=5, x=0.0, y=-0.4, vx=0.0, vy=0.8, radius=0.2, confidence=0.9)]  # north, odom
    odom_in_map = Pose2D(0.0, 0.0, math.pi / 2)  # odom's north is the map's west
    cm = global_costmap(CFG.costmap, lambda: now, lambda: odom_in_map)
    floor = lambda: cm.set_static(np.zeros((120, 120), np.int8), 0.05, -3.0, -3.0)  # noqa: E731 - each a rebuild
    floor()
    now[:] = [Person(id=5, x=0.0, y=0.0, vx=0.0, vy=0.8, radius=0.2, confidence=0.9)]  # 0.4 m on: a walk
    floor()
    assert cost(cm, KEEP_OUT + 0.5, 0.0) == 0  # walking: nothing behind them
    now[:] = [Person(id=5, x=0.0, y=0.0, vx=0.02, vy=0.0, radius=0.2, confidence=0.9)]  # paused
    floor()
    assert cost(cm, KEEP_OUT + 0.7, 0.0) == LETHAL and cost(cm, -(KEEP_OUT + 0.7), 0.0) == LETHAL  # back and on
    assert cost(cm, 0.0, KEEP_OUT + 0.4) == 0  # not across their walk
    now[:] = [Person(id=6, x=0.0, y=0.0, vx=0.0, vy=0.0, radius=0.2, confidence=0.9)]  # someone who never walked
    floor()
    assert cost(cm, KEEP_OUT + 0.5, 0.0) == 0


def test_the_planners_costmap_keeps_a_paused_pacers_whole_walk_back_out_and_the_local_one_a_second():
    """A cart pusher walked 4 m up an aisle and stands at its end: the global costmap keeps the
    whole of that walk out (they turn and walk it back: safety.people seed 104, 650 s, the way
    home planned down it), MPPI's local costmap the second of it next to them, as before."""
    from hw.interfaces import LidarScan
    from nav.walks import Walks

    t = [0.0]
    now: list[Person] = []
    walks = Walks(lambda: now, lambda: t[0])
    gcm = global_costmap(CFG.costmap, walks)
    lcm = local_costmap(CFG.costmap, walks)
    for k in range(9):  # from y = -3 to y = 1
        t[0] += 0.5
        now[:] = [Person(5, 0.0, -3.0 + 0.5 * k, 0.0, 1.0, 0.2, 0.9)]
        walks()
    t[0] += 2.0
    now[:] = [Person(5, 0.0, 1.0, 0.0, 0.0, 0.2, 0.9)]  # paused at the end
    gcm.set_static(np.zeros((200, 200), np.int8), 0.05, -5.0, -5.0)  # open floor, and a rebuild
    angles = np.linspace(-np.pi, np.pi, 360, endpoint=False).astype(np.float32)
    lcm.update(LidarScan(t[0], angles, np.full(360, np.inf, np.float32)), (0.0, 0.0, 0.0), (0.0, 0.0))  # sees nothing
    assert cost(gcm, 0.0, -2.5) == LETHAL and cost(gcm, 0.0, -0.5) == LETHAL  # the whole way back
    assert cost(gcm, 0.0, -3.0 - KEEP_OUT - 0.3) == 0  # not past where the walk began
    assert cost(lcm, 0.0, -1.0) < LETHAL == cost(gcm, 0.0, -1.0)  # 2 m back: the local second ends 1 m back
