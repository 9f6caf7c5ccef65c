"""The velocity smoother, the goal checker and the frame algebra."""
from __future__ import annotations

import math

import numpy as np
import pytest
from pydantic import ValidationError

from hw.interfaces import Twist
from hw.odometry import Pose2D
from nav.config import GoalCheckerConfig, NavConfig
from nav.frames import compose, inverse, transform_path, transform_points, yaw_error
from nav.goal_checker import GoalChecker
from nav.smoother import VelocitySmoother


def smoother() -> VelocitySmoother:
    return VelocitySmoother(NavConfig().smoother)


def test_smoother_limits_follow_the_mppi_envelope():
    cfg = NavConfig(mppi={"vx_max": 0.4, "ax_max": 2.0})
    assert cfg.smoother.max_velocity == (0.4, 0.5, 1.9)
    assert cfg.smoother.min_velocity == (-0.35, -0.5, -1.9)
    assert cfg.smoother.max_accel == (2.0, 2.5, 3.2)
    assert cfg.smoother.max_decel == (-2.0, -2.5, -3.2)


def test_smoother_override_that_would_chop_mppi_is_rejected():
    with pytest.raises(ValidationError, match="chop"):
        NavConfig(smoother={"max_velocity": (0.3, 0.5, 1.9)})
    with pytest.raises(ValidationError, match="chop"):
        NavConfig(smoother={"min_velocity": (-0.35, -0.2, -1.9)})
    wider = NavConfig(smoother={"max_velocity": (0.6, 0.5, 1.9)})
    assert wider.smoother.max_velocity == (0.6, 0.5, 1.9)


def test_smoother_ramps_at_the_accel_limit_and_clamps_velocity():
    s = smoother()
    out = [s.smooth(Twist(1.0, -1.0, 5.0), 0.05) for _ in range(20)]
    assert out[0].vx == pytest.approx(2.5 * 0.05) and out[0].vy == pytest.approx(-2.5 * 0.05)
    assert out[0].wz == pytest.approx(3.2 * 0.05)
    assert out[-1] == Twist(0.5, -0.5, 1.9)  # clamped to the envelope


def test_smoother_decelerates_and_reverses_at_the_decel_limit():
    s = smoother()
    for _ in range(10):
        s.smooth(Twist(0.5, 0.0, 0.0), 0.05)
    first = s.smooth(Twist(-0.35, 0.0, 0.0), 0.05)
    assert first.vx == pytest.approx(0.5 - 2.5 * 0.05)
    s.reset()
    assert s.smooth(Twist(0.0, 0.0, 0.0), 0.05) == Twist(0.0, 0.0, 0.0)


def test_goal_checker_tolerances_and_latch():
    g = GoalChecker(GoalCheckerConfig())
    goal = Pose2D(1.0, 1.0, 0.0)
    assert not g.reached(Pose2D(1.3, 1.0, 0.0), goal)  # 0.30 m away
    assert not g.reached(Pose2D(1.2, 1.0, 0.13), goal)  # inside xy, yaw off by 0.13 > 0.12
    assert g.reached(Pose2D(1.26, 1.0, 0.11), goal)  # xy latched, heading now inside
    g.reset()
    assert not g.reached(Pose2D(1.26, 1.0, 0.11), goal)


def test_goal_checker_wraps_yaw():
    g = GoalChecker(GoalCheckerConfig())
    assert g.reached(Pose2D(0.0, 0.0, math.pi - 0.05), Pose2D(0.0, 0.0, -math.pi + 0.05))


def test_frames_compose_inverse_and_points():
    a = Pose2D(1.0, 2.0, 0.7)
    b = Pose2D(-0.3, 0.5, -2.0)
    ident = compose(a, inverse(a))
    assert abs(ident.x) < 1e-12 and abs(ident.y) < 1e-12 and abs(ident.yaw) < 1e-12
    ab = compose(a, b)
    pt = transform_points(a, np.array([[b.x, b.y]]))[0]
    assert pt == pytest.approx([ab.x, ab.y])
    path = transform_path(a, np.array([[b.x, b.y, b.yaw]]))[0]
    assert path == pytest.approx([ab.x, ab.y, ab.yaw])
    assert yaw_error(Pose2D(yaw=3.1), Pose2D(yaw=-3.1)) == pytest.approx(2 * math.pi - 6.2)
