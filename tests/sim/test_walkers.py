"""The sim's walkers (sim/walkers.py): they walk their path at their speed, stand at each end for
their pause and walk back, start late when asked, stop short of the robot and only there, stop
and go on command, and the lidar sees them."""
from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from hw.config import HwConfig
from sim.backend import SimRobot
from sim.config import SimConfig
from sim.walkers import KEEP_CLEAR, LEG_RADIUS, footprint_gap
from sim.world import Floor, Pose2, Walker, World, ROBOT_RADIUS

pytestmark = pytest.mark.slow


def _robot(spawn=(0.6, 0.6), **walker) -> SimRobot:
    w = Walker(**{"id": "W1", "path": [[2.0, 2.0], [6.0, 2.0]], "speed": 1.0, **walker})
    world = World(name="walk", floor=Floor(x=8.0, y=4.0), spawn=Pose2(x=spawn[0], y=spawn[1], yaw=0.0),
                  pots=[], walkers=[w])
    return SimRobot(world, SimConfig(), HwConfig())


def _at(sim: SimRobot, t: float) -> tuple[float, float]:
    sim.engine.advance_to(t)
    x, y, _ = sim.walkers.positions()["W1"]
    return x, y


def test_a_walker_walks_its_path_pauses_and_comes_back():
    sim = _robot(pause=1.0, start=0.5)
    assert _at(sim, 0.4) == pytest.approx((2.0, 2.0))          # not started yet
    assert _at(sim, 2.5)[0] == pytest.approx(4.0, abs=0.02)    # 2 s at 1 m/s
    assert _at(sim, 4.6)[0] == pytest.approx(6.0, abs=0.02)    # at the end
    assert _at(sim, 5.4)[0] == pytest.approx(6.0, abs=0.02)    # standing out its pause
    assert _at(sim, 6.6)[0] == pytest.approx(4.9, abs=0.02)    # and walking back (end at 4.5 s + 1 s)
    body = sim.engine.data.xpos[sim.engine.id(mujoco.mjtObj.mjOBJ_BODY, "walker_W1")]
    assert body[0] == pytest.approx(4.9, abs=0.02)              # the body moves with it


def test_a_walker_stops_short_of_the_robot_and_goes_on_when_it_leaves():
    sim = _robot(spawn=(4.0, 2.0))
    x, _ = _at(sim, 4.0)
    gap = sim.walkers.gap("W1", 4.0, 2.0) - ROBOT_RADIUS
    assert KEEP_CLEAR - 0.02 <= gap <= KEEP_CLEAR + 0.02       # waiting, 0.3 m from the robot's body
    assert x == pytest.approx(4.0 - ROBOT_RADIUS - KEEP_CLEAR - LEG_RADIUS, abs=0.02)  # its legs lead
    sim.place(4.0, 3.5, 0.0)                                   # the robot is lifted out of the aisle
    assert _at(sim, 6.5)[0] == pytest.approx(x + 2.5, abs=0.02)  # it walks on at its speed


def test_a_walker_steps_away_from_a_robot_that_came_too_close():
    sim = _robot(path=[[3.0, 2.0], [6.0, 2.0]], spawn=(2.6, 2.0))  # the robot right behind it
    assert _at(sim, 1.0)[0] > 3.5


def test_a_held_walker_stands_until_let_go():
    sim = _robot()
    x = _at(sim, 1.0)[0]
    sim.faults.walker("W1", moving=False)
    assert _at(sim, 3.0)[0] == pytest.approx(x)
    sim.faults.walker("W1", moving=True)
    assert _at(sim, 4.0)[0] == pytest.approx(x + 1.0, abs=0.02)
    with pytest.raises(ValueError, match="no walker 'W9'"):
        sim.faults.walker("W9", moving=True)


def test_the_lidar_sees_a_walker():
    sim = _robot(spawn=(1.0, 2.0), start=100.0)  # standing at (2, 2), 1 m ahead of the robot
    sim.engine.advance_to(0.3)
    scan = sim.lidar.latest_scan()
    wrapped = np.arctan2(np.sin(scan.angles), np.cos(scan.angles))
    ahead = scan.ranges[np.abs(wrapped) < 0.1]
    assert ahead.min() < 1.0  # a body ~0.8-0.95 m ahead, not the wall 7 m away


def test_the_footprint_is_the_legs_and_the_cart_ahead():
    """A person facing +x at the origin, 0.45 m wide: legs 0.07 m in radius at y = +-0.1125; a
    cart pusher (0.9 m) has a 0.6 x 0.9 m cart from 0.15 to 0.75 m ahead."""
    assert footprint_gap(0, 0, 0.0, 0.225, 0.5, 0.1125) == pytest.approx(0.43)
    assert footprint_gap(0, 0, 0.0, 0.225, 0.0, 0.5) == pytest.approx(0.5 - 0.1125 - 0.07)
    assert footprint_gap(0, 0, math.pi, 0.225, -0.5, -0.1125) == pytest.approx(0.43)  # turned round
    assert footprint_gap(0, 0, 0.0, 0.45, 1.0, 0.0) == pytest.approx(0.25)  # the cart's front
    assert footprint_gap(0, 0, 0.0, 0.45, 0.5, 0.0) < 0  # inside the cart


def test_a_cart_pusher_turns_round_at_the_end_sweeping_the_cart_round_not_jumping_it():
    """At the east end (6, 2), arriving at 4 s with a 3 s pause, a cart pusher stands facing the
    way they came, turns round in the pause's last second (half way through, the cart to one
    side of them), and walks back at 7 s."""
    sim = _robot(width=0.9, pause=3.0)
    _at(sim, 5.5)
    cart = lambda x, y: sim.walkers.gap("W1", x, y) < 0  # noqa: E731 - inside the footprint
    assert cart(6.45, 2.0) and not cart(5.55, 2.0)  # standing out the pause, facing east
    _at(sim, 6.5)
    assert not cart(6.45, 2.0) and not cart(5.55, 2.0)  # swinging round: the cart to one side
    assert cart(6.0, 2.45) or cart(6.0, 1.55)
    _at(sim, 6.99)
    assert cart(5.55, 2.0) and not cart(6.45, 2.0)  # turned round
    assert _at(sim, 7.5)[0] == pytest.approx(5.5, abs=0.03)  # and walking back from 7 s


def test_a_walker_that_does_not_yield_walks_on_into_the_robot():
    sim = _robot(spawn=(4.0, 2.0), yields=False)
    assert _at(sim, 1.8)[0] == pytest.approx(3.8, abs=0.02)   # a yielding one waits at 3.41 (test above)
    assert sim.walkers.gap("W1", 4.0, 2.0) - ROBOT_RADIUS < 0    # its legs are where the robot was


def test_a_worker_who_stays_put_never_moves():
    sim = _robot(path=[[3.0, 2.0]], spawn=(3.6, 2.0))
    assert _at(sim, 3.0) == pytest.approx((3.0, 2.0))
    sim.place(1.0, 1.0, 0.0)
    assert _at(sim, 6.0) == pytest.approx((3.0, 2.0))


def test_a_crouching_worker_is_one_block_to_the_lidar_and_the_judges():
    """Facing +x at (2, 2): a 0.5 x 0.6 m block. The lidar 1 m west of it sees one solid face
    (no gap between legs), 0.75 m from the robot's centre less the lidar's offset."""
    assert footprint_gap(0, 0, 0.0, 0.3, 0.5, 0.0, crouching=True) == pytest.approx(0.25)
    assert footprint_gap(0, 0, 0.0, 0.3, 0.0, 0.5, crouching=True) == pytest.approx(0.2)
    assert footprint_gap(0, 0, 0.0, 0.3, 0.0, 0.0, crouching=True) == pytest.approx(-0.25)
    sim = _robot(path=[[2.0, 2.0]], posture="crouching", spawn=(1.0, 2.0))
    sim.engine.advance_to(0.3)
    assert sim.walkers.gap("W1", 1.0, 2.0) == pytest.approx(0.75)
    assert type(sim.walkers.gap("W1", 2.0, 2.0)) is float      # inside the block too: a plain float for the judges' JSON
    scan = sim.lidar.latest_scan()
    wrapped = np.arctan2(np.sin(scan.angles), np.cos(scan.angles))
    face = scan.ranges[np.abs(wrapped) < 0.25]  # +-0.25 rad at ~0.75 m: +-0.19 m of its 0.6 m face
    assert np.all(face < 0.85)                  # a solid face: no ray passes between legs
    geoms = [mujoco.mj_id2name(sim.engine.model, mujoco.mjtObj.mjOBJ_GEOM, g) or "" for g in range(sim.engine.model.ngeom)]
    assert not any(n.startswith("walker_W1_leg") for n in geoms) and "walker_W1_body" in geoms
