"""Where to wait for people (nav.refuge): out of everyone's way, not just the nearest person's.

The layout is safety.people's seed 4, where the robot backed off from a grower into the cross
aisle a cart pusher walks without yielding: rows of pots east of x 8.9 with aisles between them
at y 3.5, 4.5 and 5.5, the bays' divider wall west of x 7.25 (both inflated), and the cross
aisle between them."""
from __future__ import annotations

import numpy as np

from nav.config import NavConfig
from nav.costmap.grid import LETHAL, CostGrid
from nav.walks import WALKING
from nav.refuge import refuge_heading

LAYER = NavConfig().costmap.global_costmap.people
RADIUS = NavConfig().costmap.robot_radius
MOUTH = np.array([9.1, 4.4])  # the robot, at the mouth of the aisle y 4.5


def _floor(here: np.ndarray) -> tuple[CostGrid, np.ndarray, np.ndarray]:
    """Open floor 3 x 3 m round ``here`` (5 cm), as the local costmap rolls with the robot, and
    its cells' centres (x, y) to draw on."""
    grid = CostGrid.filled(60, 60, 0.05, here[0] - 1.5, here[1] - 1.5)
    iy, ix = np.mgrid[0:60, 0:60]
    x, y = grid.geometry.centre_of(ix, iy)
    return grid, x, y


def _greenhouse() -> CostGrid:
    """3 x 3 m round the robot (5 cm), as the local costmap rolls with it."""
    grid, x, y = _floor(MOUTH)
    grid.data[(x >= 8.9) & (np.abs(y - np.round(y)) < 0.3)] = LETHAL  # the rows, inflated
    grid.data[x <= 7.25] = LETHAL  # the divider
    return grid


def _heading(people, want=LAYER.wait_clearance):
    rows = np.array([[p[0], p[1], p[2], p[3], p[4]] for p in people], dtype=float)
    return _u(refuge_heading(MOUTH, rows, _greenhouse(), RADIUS, LAYER.clearance, want, LAYER.lane_time, WALKING))


def _u(step):
    return None if step is None else step.heading


GROWER = (9.7, 4.5, 0.0, 0.0, 0.2)  # stopped for the robot in their aisle, 0.18 m body to body
CART = (8.0, 2.8, 0.0, 0.7, 0.35)  # walking north up the cross aisle, not yielding


def test_backing_off_from_a_grower_alone_goes_out_into_the_cross_aisle():
    u = _heading([GROWER])
    assert u is not None and u[0] < -0.5  # west, away from them: the cross aisle is free


def test_with_a_cart_coming_up_the_cross_aisle_it_does_not_back_off_into_the_carts_way():
    u = _heading([GROWER, CART])
    assert u is None or u[0] > -1e-9


def test_a_robot_in_a_carts_way_leaves_it_on_its_own_side_never_across_in_front():
    here = np.array([8.3, 4.5])  # in the cross aisle, east of the cart's line
    rows = np.array([CART], dtype=float)
    u = _u(refuge_heading(here, rows, _greenhouse(), RADIUS, LAYER.clearance, LAYER.clearance, LAYER.lane_time, WALKING))
    assert u is not None and u[0] > 0.5  # east, into the aisle mouth


def test_a_robot_already_out_of_everyones_way_stays():
    rows = np.array([CART], dtype=float)
    assert _u(refuge_heading(MOUTH + [0.3, 0.0], rows, _greenhouse(), RADIUS, LAYER.clearance, LAYER.clearance,
                             LAYER.lane_time, WALKING)) is None


def test_behind_a_walker_it_crosses_their_lane_to_a_refuge_beyond():
    """safety.people seed 1: a grower stopped for the robot in their aisle (their last stride
    towards it), the only refuge across the cross aisle a cart pusher walks; walking away, the
    robot crosses behind them to wait beyond their lane; coming, it does not cross in front
    (standing deep in the grower's lane once let the way go as deep into the cart's)."""
    here = np.array([12.3, 2.5])
    grid, x, y = _floor(here)
    grid.data[(x <= 12.1) & (np.abs(y - 2.5) > 0.2)] = LETHAL  # benches either side of the aisle, inflated
    grid.data[x >= 13.78] = LETHAL  # the east wall, inflated
    grower = (11.0, 2.5, 0.7, 0.0, 0.35)  # a cart, stopped: the velocity of their last stride
    away = (12.75, 3.6, 0.0, 0.7, 0.35)  # the cross aisle's cart pusher, walking north, away

    def heading(*people):
        return _u(refuge_heading(here, np.array(people, dtype=float), grid, RADIUS, LAYER.clearance,
                                 LAYER.wait_clearance, LAYER.lane_time, WALKING))
    u = heading(grower, away)
    assert u is not None and u[0] > 0.5  # east, across the cart's lane behind it
    coming = (12.75, 3.6, 0.0, -0.7, 0.35)
    assert heading(grower, coming) is None  # across its way ahead: wait in the aisle


def test_the_refuge_chosen_is_kept_while_a_carts_heading_estimate_swings():
    """safety.people seed 2, 1,403-1,407 s: a cart coming up a cross aisle at the robot, the
    tracker's heading for it swinging a few degrees either way; chosen afresh, the refuge
    flipped from one side of its lane to the other each time, the robot stepped west, east,
    west, and was still in the lane when the cart walked into it."""
    here = np.array([6.0, 5.5])
    grid, _, _ = _floor(here)  # open floor either side

    def step(vx, keep=None):
        cart = (6.0, 3.5, vx, 0.7, 0.35)
        return refuge_heading(here, np.array([cart], dtype=float), grid, RADIUS, LAYER.clearance,
                              LAYER.clearance, LAYER.lane_time, WALKING, keep)
    west, east = step(0.015), step(-0.015)  # leaning east, the lane leaves more room west; and back
    assert west.heading[0] < -0.5 and east.heading[0] > 0.5  # afresh, the side flips
    kept = step(-0.015, keep=west.refuge)
    assert kept.heading[0] < -0.5 and np.allclose(kept.refuge, west.refuge)  # kept: still west
    far = west.refuge + [-1.0, 0.0]  # a refuge a metre farther than the nearest is not kept
    assert step(-0.015, keep=far).heading[0] > 0.5


def test_a_robot_a_little_off_a_carts_line_never_crosses_it_ahead_of_them():
    """0.2 m east of the line of a cart coming north: with room east, it goes east; with none (a
    wall 0.45 m off) it does not step west across the line in front of the cart, only on along
    its own side, round the far end of the lane, or not at all."""
    here = np.array([6.2, 6.0])
    cart = np.array([(6.0, 3.0, 0.0, 0.7, 0.35)], dtype=float)  # its lane ends 1 m north of the robot
    open_floor, _, _ = _floor(here)
    walled, x, _ = _floor(here)
    walled.data[x >= here[0] + 0.45] = LETHAL

    def heading(grid):
        return _u(refuge_heading(here, cart, grid, RADIUS, LAYER.clearance, LAYER.clearance, LAYER.lane_time, WALKING))
    assert heading(open_floor)[0] > 0.5
    u = heading(walled)
    assert u is None or u[0] > -1e-9


def test_a_refuge_keeps_out_of_where_a_cart_turned_round():
    """safety.people held-out seed 101, 2,225 s: in the north aisle, a grower who had stopped for
    the robot creeps on towards it; the way out west ends 0.95 m from where a cart pusher who
    does not yield had turned round at the end of their cross aisle 10 s before (the cart was
    walking south, away). Knowing the turn, the robot does not wait there: the cart came back
    and, turning, swept it to 0.12 m."""
    here = np.array([2.21, 6.67])
    grid, x, y = _floor(here)
    grid.data[y >= 7.0] = LETHAL  # the north wall, inflated
    grid.data[(y <= 6.2) & (x >= 1.5)] = LETHAL  # the last row's pots, inflated; the cross aisle west of them
    grower = (2.8, 6.5, -0.15, 0.0, 0.27)
    cart = (1.0, 4.5, 0.0, -0.9, 0.45)  # walking south, away, 2 m off

    def step(turns=None):
        return _u(refuge_heading(here, np.array([grower, cart], dtype=float), grid, RADIUS, LAYER.clearance,
                                 LAYER.wait_clearance, LAYER.lane_time, WALKING, None, turns))
    u = step()
    assert u is not None and u[0] < -0.5  # unknowing, west, towards the end of the cart's walk
    assert step(np.array([[1.1, 6.6, 0.9]])) is None  # knowing the turn: no refuge in reach, it stands
