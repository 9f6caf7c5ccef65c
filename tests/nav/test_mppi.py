"""MPPI in a closed loop on an ideal kinematic base (no simulator): the seed's Omni properties,
determinism, the envelope, and 'no valid control' when boxed in. The same properties are run
through the wheels in the MuJoCo greenhouse in test_navigation_sim.py."""
from __future__ import annotations

import math

import numpy as np
import pytest

from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import LETHAL
from nav.mppi.config import MppiConfig
from nav.mppi.controller import MppiController, NoValidControl
from nav.mppi.smoothing import SG, enforce_limits, savitzky_golay
from nav.config import NavConfig
from tests.nav.builders import dummy_costmap, straight_path

CM = CostmapsConfig()


def mppi(**over) -> MppiController:
    cfg = NavConfig(mppi=over).mppi  # derived values (GoalAngle reach) as the runtime has them
    return MppiController(cfg, CM)


def drive(ctrl, goal, grid, start=(0.0, 0.0, 0.0), steps=400, path=None, lag=0.0):
    """Integrate each command for one 50 ms period; stop inside 0.25 m / 0.12 rad at rest.
    ``lag`` > 0 is a first-order base lag (time constant in s) between command and velocity."""
    x, y, yaw = start
    v = np.zeros(3)
    poses = [(x, y, yaw)]
    if path is None:
        path = with_headings(straight_path((x, y), goal[:2]), goal[2])
    for _ in range(steps):
        ahead = path[int(np.argmin(np.hypot(path[:, 0] - x, path[:, 1] - y))):]  # pruned, as the navigator does
        cmd = np.array(ctrl.compute((x, y, yaw), tuple(v), ahead if len(ahead) > 1 else path[-2:], goal, grid))
        v = cmd if lag == 0.0 else v + (cmd - v) * (1.0 - math.exp(-0.05 / lag))
        x += (v[0] * math.cos(yaw) - v[1] * math.sin(yaw)) * 0.05
        y += (v[0] * math.sin(yaw) + v[1] * math.cos(yaw)) * 0.05
        yaw += v[2] * 0.05
        poses.append((x, y, yaw))
        err = abs(math.remainder(yaw - goal[2], 2 * math.pi))
        if math.hypot(x - goal[0], y - goal[1]) < 0.25 and err < 0.12 and np.abs(v).max() < 0.05:
            return np.array(poses), True
    return np.array(poses), False


def with_headings(xy, goal_yaw):
    """Path headings as the navigator gives them: the tangent, the goal's yaw at the end."""
    d = np.diff(xy, axis=0)
    return np.column_stack([xy, np.append(np.arctan2(d[:, 1], d[:, 0]), goal_yaw)])


def open_grid():
    return dummy_costmap(120, 120, origin=(-3.0, -3.0))


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_omni_strafes_to_a_goal_beside_it(side):
    poses, ok = drive(mppi(), (0.0, side, 0.0), open_grid())
    assert ok
    assert np.max(np.abs(poses[:, 2])) < 0.1


def test_omni_strafe_survives_a_lagging_base():
    poses, ok = drive(mppi(), (0.0, 1.0, 0.0), open_grid(), lag=0.1)
    assert ok
    assert np.max(np.abs(poses[:, 2])) < 0.1


def test_lateral_speeds_below_the_threshold_read_as_zero():
    grid = open_grid()
    path = np.column_stack([straight_path((0, 0), (0, 1)), np.zeros(21)])
    out = [mppi().compute((0, 0, 0), (0.0, vy, 0.0), path, (0, 1, 0), grid) for vy in (0.0, 0.0009, 0.3)]
    assert out[0] == out[1]  # 0.0009 < min_y_velocity_threshold 0.001
    assert out[2] != out[0]  # a real strafe is the rollout's starting velocity


def test_left_and_right_are_mirror_images():
    left, _ = drive(mppi(), (0.0, 1.0, 0.0), open_grid())
    right, _ = drive(mppi(), (0.0, -1.0, 0.0), open_grid())
    assert abs(len(left) - len(right)) <= 10
    n = min(len(left), len(right))
    assert np.max(np.abs(left[:n, 1] + right[:n, 1])) < 0.1


def test_diff_drive_turns_to_reach_the_same_goal():
    poses, ok = drive(mppi(motion_model="diff"), (0.0, 1.0, 0.0), open_grid(), steps=600)
    assert ok
    assert np.max(np.abs(poses[:, 2])) > 0.5


def test_goes_around_a_wall_without_touching_it():
    grid = open_grid()
    grid.data[50:70, 75:78] = LETHAL  # wall across x 0.75..0.9, y -0.5..0.5
    from nav.costmap.inflation import InflationLayer
    grid.data[:] = InflationLayer(CM.resolution, CM.robot_radius, CM.inflation_radius,
                                  CM.cost_scaling_factor).apply(grid.data)
    # A plan around the wall's north end, as NavFn would give it.
    way = np.vstack([straight_path((0.0, 0.0), (0.5, 0.85)), straight_path((0.5, 0.85), (1.2, 0.85)),
                     straight_path((1.2, 0.85), (1.6, 0.0))])
    path = with_headings(way, 0.0)
    poses, ok = drive(mppi(), (1.6, 0.0, 0.0), grid, path=path, steps=600)
    assert ok
    cost = grid.cost_at(poses[:, 0], poses[:, 1])
    assert np.all(cost < LETHAL)


def test_boxed_in_raises_no_valid_control():
    grid = open_grid()
    grid.data[:] = LETHAL
    grid.data[60, 60] = 0  # only the cell the robot stands in
    with pytest.raises(NoValidControl):
        mppi().compute((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), np.array([[0, 0, 0], [1, 0, 0.0]]), (1.0, 0.0, 0.0), grid)


def test_same_seed_same_commands_and_commands_inside_the_envelope():
    grid = open_grid()
    path = np.column_stack([straight_path((0, 0), (2, 0)), np.zeros(41)])
    a, b = mppi(), mppi()
    for _ in range(20):
        ca = a.compute((0, 0, 0), (0.2, 0, 0), path, (2, 0, 0), grid)
        cb = b.compute((0, 0, 0), (0.2, 0, 0), path, (2, 0, 0), grid)
        assert ca == cb
        c = MppiConfig()
        assert c.vx_min - 1e-6 <= ca[0] <= c.vx_max + 1e-6 and abs(ca[1]) <= c.vy_max + 1e-6
        assert abs(ca[2]) <= c.wz_max + 1e-6


def test_savitzky_golay_keeps_a_constant_and_a_ramp():
    assert SG.sum() == pytest.approx(1.0)
    u = np.full((56, 3), 0.3, np.float32)
    assert np.allclose(savitzky_golay(u, np.full((4, 3), 0.3, np.float32)), 0.3, atol=1e-6)
    ramp = np.repeat(np.arange(60, dtype=np.float32)[:, None] * 0.01, 3, axis=1)
    out = savitzky_golay(ramp[4:56 + 4 - 4], ramp[:4])
    assert np.allclose(out[:40], ramp[4:44], atol=1e-5)  # quadratic fit is exact on a line


def test_trajectories_for_drawing_and_reset():
    grid = open_grid()
    path = np.column_stack([straight_path((0, 0), (2, 0)), np.zeros(41)])
    ctrl = mppi()
    assert ctrl.optimal_trajectory is None
    for _ in range(10):
        ctrl.compute((0, 0, 0), (0.3, 0, 0), path, (2, 0, 0), grid)
    opt, samples = ctrl.optimal_trajectory, ctrl.sampled_trajectories
    assert opt.shape == (56, 3) and samples.shape == (16, 56, 3)
    assert opt[-1, 0] > 0.5 and abs(opt[-1, 1]) < 0.2  # heads down the path
    assert not np.allclose(samples[0], samples[1])
    ctrl.reset()
    assert ctrl.optimal_trajectory is None and not ctrl.optimizer.u.any()


def test_enforce_limits_walks_the_acceleration_limit_from_the_current_velocity():
    lo, hi = np.array([-0.35, -0.5, -1.9], np.float32), np.array([0.5, 0.5, 1.9], np.float32)
    acc = np.array([2.5, 2.5, 3.2], np.float32)
    u = np.tile(np.array([[1.0, -1.0, 0.0]], np.float32), (56, 1))
    out = enforce_limits(u, lo, hi, acc, 0.05, np.zeros(3, np.float32))
    assert out[0] == pytest.approx([0.125, -0.125, 0.0])  # one step of 2.5 m/s^2 x 0.05 s
    assert out[3] == pytest.approx([0.5, -0.5, 0.0])  # then the velocity limit
    assert np.all(np.abs(np.diff(out, axis=0)) <= acc * 0.05 + 1e-6)
