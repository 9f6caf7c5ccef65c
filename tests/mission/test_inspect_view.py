"""The patrol's wrist view (issue 30): ``inspect_plant`` from the ideal approach pose, the IK look
at the plant from the preset's own range elsewhere; with the arm driven by its controller (its
real sag), ``inspect_plant`` holds the whole plant top in the frame where the seed's ``inspect``
does not."""
from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import math  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from arm import limits  # noqa: E402
from arm.kinematics import camera_ray  # noqa: E402
from arm.presets import PRESETS  # noqa: E402
from hw.odometry import Pose2D  # noqa: E402
from lupin.bench.perception import approach_pose, move_arm, plant_in_view  # noqa: E402
from mission.patrol.config import PatrolConfig  # noqa: E402
from mission.patrol.inspect_view import RANGE_BAND, InspectView  # noqa: E402
from mission.runtime.config import LupinConfig  # noqa: E402
from mission.runtime.sim_runtime import start_sim_runtime  # noqa: E402
from nav.frames import compose, inverse  # noqa: E402
from sim.world import load_default_world  # noqa: E402

CONFIG = LupinConfig()
IDEAL = Pose2D(2.0, 0.5, math.pi / 2)


def test_the_preset_from_the_ideal_pose_the_ik_look_from_elsewhere():
    view = InspectView(CONFIG.arm, PatrolConfig())
    goal, label = view.goal(IDEAL, compose(IDEAL, Pose2D(0.01, -0.01, 0.02)))
    assert label == "inspect_plant" and tuple(goal.values()) == PRESETS["inspect_plant"]
    k = CONFIG.arm.kinematics
    reach = np.linalg.norm(view.spot - camera_ray(PRESETS["inspect_plant"], k)[0])
    for off in (Pose2D(-0.1, 0.0, 0.0), Pose2D(0.05, 0.08, -0.1), Pose2D(0.0, -0.1, 0.1)):
        here = compose(IDEAL, off)
        goal, label = view.goal(IDEAL, here)
        assert label == "aim" and limits.within(goal), off
        # the spot the preset frames from the ideal pose, seen from about the preset's range
        spot = compose(inverse(off), Pose2D(view.spot[0], view.spot[1], 0.0))
        p, d = camera_ray(goal, k)
        target = np.array([spot.x, spot.y, view.spot[2]])
        along = float((target - p) @ d)
        assert np.linalg.norm(target - p - along * d) < 0.01 and abs(along - reach) <= RANGE_BAND + 1e-3, off


@pytest.mark.slow
def test_the_whole_plant_top_is_in_the_frame_under_the_real_sag():
    world = load_default_world()
    pot = next(p for p in world.pots if p.id == "P03")  # three blooms: the widest plant top
    rt = start_sim_runtime(world, CONFIG)
    try:
        rt.robot.scheduler.run_for(0.3)
        rt.sim.place(*approach_pose(pot))
        seen = {}
        for name in ("inspect", "inspect_plant"):
            assert move_arm(rt, "home") and move_arm(rt, name)
            q = np.array([rt.sim.servos.joint_position(j) for j in ("shoulder_pan", "shoulder_lift", "elbow", "wrist")])
            assert 0.02 < np.abs(q - PRESETS[name]).max() < 0.06  # driven, not placed: it sags
            seen[name] = plant_in_view(rt.sim, pot, CONFIG)
    finally:
        rt.close()
    assert seen == {"inspect": False, "inspect_plant": True}
