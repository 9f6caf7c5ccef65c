"""The outline's point test, which takes all capsules at once, against the plain definition: the
chassis box grown by the margin, or within radius + margin of a capsule's segment, capsule by
capsule."""
from __future__ import annotations

import numpy as np

from arm.config import KinematicsConfig
from arm.outline import arm_capsules
from hw.robot_outline import Outline


def plainly_inside(outline: Outline, p: np.ndarray, margin: float) -> np.ndarray:
    hit = (np.abs(p[:, 0]) < outline.half_length + margin) & (np.abs(p[:, 1]) < outline.half_width + margin)
    for a, b in outline.capsules.segments:
        d = b - a
        n = float(d @ d)
        t = np.clip(((p - a) @ d) / n, 0.0, 1.0) if n > 0 else np.zeros(len(p))
        hit |= (((p - a) - t[:, None] * d) ** 2).sum(axis=1) < (outline.capsules.radius + margin) ** 2
    return hit


def test_the_outline_holds_the_same_points_as_the_box_and_capsules_plainly_tested():
    rng = np.random.default_rng(7)
    k = KinematicsConfig()
    held = 0
    for case in range(200):
        arm = arm_capsules(rng.uniform(-np.pi, np.pi, 4), k)
        outline = Outline(0.165, 0.13, arm) if case % 5 else Outline(0.165, 0.13)
        p = rng.uniform(-0.7, 0.7, (1000, 2))
        margin = float(rng.uniform(0.0, 0.05))
        got = outline.inside(p[:, 0], p[:, 1], margin)
        assert (got == plainly_inside(outline, p, margin)).all()
        held += int(got.sum())
    assert held > 10_000  # the points near the robot were tested, not only the far ones


def test_points_in_any_shape_broadcast_as_numpy_does():
    outline = Outline(0.165, 0.13)
    x = np.array([[0.0, 0.2, 0.5]])
    y = np.array([[0.0], [0.16]])
    assert outline.inside(x, y, 0.02).tolist() == [[True, False, False], [False, False, False]]
    assert outline.inside(x, y, 0.04).tolist() == [[True, True, False], [True, True, False]]
