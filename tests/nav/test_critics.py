"""Each MPPI critic on hand-made trajectories: does it prefer what Nav2's critic prefers?"""
from __future__ import annotations

import math

import numpy as np
import pytest

from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import INSCRIBED, LETHAL
from nav.config import NavConfig
from nav.mppi.critic_data import CriticData
from nav.mppi.critics import make_critics
from nav.mppi.critics.constraint import ConstraintCritic
from nav.mppi.critics.goal import GoalCritic
from nav.mppi.critics.goal_angle import GoalAngleCritic
from nav.mppi.critics.obstacles import ObstaclesCritic
from nav.mppi.critics.path_align import PathAlignCritic
from nav.mppi.critics.path_angle import PathAngleCritic
from nav.mppi.critics.path_follow import PathFollowCritic
from nav.mppi.critics.prefer_forward import PreferForwardCritic
from tests.nav.builders import dummy_costmap, greenhouse_grid, straight_path

T, DT = 56, 0.05
CFG = NavConfig().mppi  # with the values derived for the Omni model
CM = CostmapsConfig()


def line_traj(vx=0.0, vy=0.0, wz=0.0, x0=0.0, y0=0.0, yaw0=0.0):
    """(3, 1, T) velocities and poses of a constant twist from a pose."""
    v = np.zeros((3, 1, T), np.float32)
    v[0], v[1], v[2] = vx, vy, wz
    traj = np.zeros((3, 1, T), np.float32)
    x, y, yaw = x0, y0, yaw0
    for t in range(T):
        x += (vx * math.cos(yaw) - vy * math.sin(yaw)) * DT
        y += (vx * math.sin(yaw) + vy * math.cos(yaw)) * DT
        yaw += wz * DT
        traj[:, 0, t] = x, y, yaw
    return v, traj


def data_for(trajs, path=None, goal=(2.0, 0.0, 0.0), grid=None, pose=(0.0, 0.0, 0.0)):
    v = np.concatenate([t[0] for t in trajs], axis=1)
    traj = np.concatenate([t[1] for t in trajs], axis=1)
    if path is None:
        xy = straight_path((pose[0], pose[1]), goal[:2])
        path = np.column_stack([xy, np.full(len(xy), goal[2])])
    grid = grid if grid is not None else dummy_costmap(120, 120, origin=(-3.0, -3.0))
    return CriticData(np.asarray(pose, np.float32), v, traj, path, np.asarray(goal, np.float32), grid, DT,
                      np.zeros(v.shape[1], np.float32))


def scores(critic, data):
    critic.score(data)
    return data.costs


def test_factory_builds_the_eight_in_config_order_and_rejects_unknown_names():
    assert [type(c).__name__ for c in make_critics(CFG, CM)] == [
        "ConstraintCritic", "ObstaclesCritic", "GoalCritic", "GoalAngleCritic", "PathAlignCritic",
        "PathFollowCritic", "PathAngleCritic", "PreferForwardCritic"]
    with pytest.raises(ValueError, match="unknown MPPI critic"):
        make_critics(CFG.model_copy(update={"critics": ("goal", "dwb")}), CM)


def test_goal_critic_prefers_closing_in_and_is_off_far_away():
    c = GoalCritic(CFG.critic.goal, CM)
    near = data_for([line_traj(vx=0.3), line_traj(vx=-0.3)], goal=(1.0, 0.0, 0.0))
    s = scores(c, near)
    assert s[0] < s[1]
    far = data_for([line_traj(vx=0.3), line_traj(vx=-0.3)], goal=(3.0, 0.0, 0.0))
    assert np.all(scores(c, far) == 0.0)  # beyond 1.4 m


def test_goal_angle_critic_prefers_the_goal_heading_within_reach():
    params = CFG.critic.goal_angle.model_copy(update={"threshold_to_consider": 1.4})
    c = GoalAngleCritic(params, CM)
    s = scores(c, data_for([line_traj(wz=0.0), line_traj(wz=0.5)], goal=(1.0, 0.0, 0.0)))
    assert s[0] == pytest.approx(0.0) and s[1] > 0.5
    wrapped = scores(c, data_for([line_traj(yaw0=math.pi - 0.01)], goal=(1.0, 0.0, -math.pi + 0.01)))
    assert wrapped[0] < 3.0 * 0.03  # wraps at +-pi


def test_prefer_forward_penalises_reversing_only():
    c = PreferForwardCritic(CFG.critic.prefer_forward, CM)
    s = scores(c, data_for([line_traj(vx=0.3), line_traj(vx=-0.3), line_traj(vy=0.4)]))
    assert s[0] == 0.0 and s[2] == 0.0
    assert s[1] == pytest.approx(1.0 * 0.3 * T * DT, rel=1e-5)


def test_constraint_critic_charges_only_the_combined_speed_over_vx_max():
    c = ConstraintCritic(CFG.critic.constraint, CM, CFG.vx_min, CFG.vx_max)
    s = scores(c, data_for([line_traj(vx=0.5), line_traj(vx=0.5, vy=0.5), line_traj(vx=-0.35)]))
    assert s[0] == 0.0 and s[2] == 0.0
    assert s[1] == pytest.approx(4.0 * (math.hypot(0.5, 0.5) - 0.5) * T * DT, rel=1e-4)


def test_path_align_prefers_the_path_and_waits_for_progress():
    c = PathAlignCritic(CFG.critic.path_align, CM)
    goal = (3.0, 0.0, 0.0)
    s = scores(c, data_for([line_traj(vx=0.5), line_traj(vx=0.5, vy=0.1)], goal=goal))
    assert s[0] < 0.01 and s[1] > s[0] + 0.5
    slow = scores(c, data_for([line_traj(vx=0.01), line_traj(vx=0.01, vy=0.05)], goal=goal))
    assert np.all(slow == 0.0)  # has not reached offset_from_furthest (20) path points


def test_path_align_steps_aside_when_the_path_is_blocked():
    grid = dummy_costmap(120, 120, origin=(-3.0, -3.0))
    grid.data[58:62, 70:80] = LETHAL  # across the path at x 0.5..1.0
    c = PathAlignCritic(CFG.critic.path_align, CM)
    s = scores(c, data_for([line_traj(vx=0.5), line_traj(vx=0.5, vy=0.1)], goal=(3.0, 0.0, 0.0), grid=grid))
    assert np.all(s == 0.0)


def test_path_follow_rewards_progress_along_the_path():
    c = PathFollowCritic(CFG.critic.path_follow, CM)
    s = scores(c, data_for([line_traj(vx=0.5), line_traj(vx=0.1), line_traj(vy=0.3)], goal=(3.0, 0.0, 0.0)))
    assert s[0] < s[1] < s[2]
    near = scores(c, data_for([line_traj(vx=0.5)], goal=(1.0, 0.0, 0.0)))
    assert near[0] == 0.0  # off within 1.4 m


@pytest.mark.parametrize("mode", ["forward", "bidirectional", "path_orientation"])
def test_path_angle_turns_toward_the_path_only_when_far_off(mode):
    params = CFG.critic.path_angle.model_copy(update={"mode": mode})
    c = PathAngleCritic(params, CM)
    # Robot heading +90 deg, path (and its orientation) along +x.
    path = np.column_stack([straight_path((0.0, 0.0), (3.0, 0.0)), np.zeros(61)])
    s = scores(c, data_for([line_traj(yaw0=math.pi / 2, wz=-1.0), line_traj(yaw0=math.pi / 2, wz=0.0)],
                           path=path, goal=(3.0, 0.0, 0.0), pose=(0.0, 0.0, math.pi / 2)))
    assert s[0] < s[1]
    aligned = scores(c, data_for([line_traj(vx=0.3)], path=path, goal=(3.0, 0.0, 0.0)))
    assert aligned[0] == 0.0


def test_obstacles_critic_collision_margin_repulsion_and_fail_flag():
    grid = greenhouse_grid()  # origin (0, 0); pots at x 2..5, rows y 1, 2, 3
    c = ObstaclesCritic(CFG.critic.obstacles, CM)
    aisle = line_traj(vx=0.4, x0=1.5, y0=0.5)  # the south aisle, clear of the pots
    into_pot = line_traj(vy=0.4, x0=2.0, y0=0.5)  # straight at P01
    hugging = line_traj(vx=0.4, x0=1.5, y0=0.68)  # inside the halo, outside inscribed
    d = data_for([aisle, into_pot, hugging], grid=grid, goal=(5.0, 0.5, 0.0), pose=(1.5, 0.5, 0.0))
    s = scores(c, d)
    assert s[1] >= 20.0 * 10000.0  # collision cost, critical weight
    assert s[0] < s[2] < s[1]
    assert not d.fail
    boxed = data_for([into_pot], grid=grid, goal=(5.0, 0.5, 0.0), pose=(2.0, 0.5, 0.0))
    scores(c, boxed)
    assert boxed.fail


def test_obstacles_critic_treats_off_map_and_inscribed_as_collision():
    grid = dummy_costmap(20, 20, origin=(-0.5, -0.5))
    grid.data[10, 15] = INSCRIBED
    c = ObstaclesCritic(CFG.critic.obstacles, CM)
    s = scores(c, data_for([line_traj(vx=0.5), line_traj(vy=0.1)], grid=grid, goal=(0.3, 0.0, 0.0)))
    assert s[0] >= 20.0 * 10000.0  # leaves the 1 x 1 m map
    assert s[1] == 0.0


def test_path_align_is_the_mean_offset_from_the_path():
    c = PathAlignCritic(CFG.critic.path_align, CM)
    path = np.column_stack([straight_path((0.0, 0.0), (3.0, 0.0)), np.zeros(61)])
    for off in (0.1, -0.2):  # a robot beside the path driving parallel to it
        s = scores(c, data_for([line_traj(vx=0.5, y0=off)], path=path, goal=(3.0, 0.0, 0.0), pose=(0.0, off, 0.0)))
        assert s[0] == pytest.approx(14.0 * abs(off), abs=1e-3)  # weight x offset


def test_obstacles_critic_adds_critical_and_repulsion_terms_and_drops_repulsion_near_the_goal():
    grid = dummy_costmap(120, 120, origin=(-3.0, -3.0))
    cost = 230
    grid.data[60, 60] = cost  # the cell at (0, 0)
    d = math.log(253.0 / cost) / CM.cost_scaling_factor  # distance past the footprint
    p = CFG.critic.obstacles
    parked, free = line_traj(x0=0.01, y0=0.01), line_traj(x0=1.01, y0=0.01)
    far = scores(ObstaclesCritic(p, CM), data_for([parked, free], grid=grid, goal=(2.0, 0.0, 0.0)))
    critical = p.critical_weight * T * (p.collision_margin_distance - d)
    repulsion = p.repulsion_weight * T * (CM.inflation_radius - d) / T
    assert far[1] == 0.0
    assert far[0] == pytest.approx(critical + repulsion, rel=1e-4)
    near = scores(ObstaclesCritic(p, CM), data_for([parked, free], grid=grid, goal=(0.3, 0.0, 0.0)))
    assert near[0] == pytest.approx(critical, rel=1e-4)
