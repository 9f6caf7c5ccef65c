"""Camera aiming with casadi: within the windows, on target (checked in MuJoCo), honest failures."""
import numpy as np
import pytest

from arm import limits
from arm.aim import CameraAim, sample_reachable_targets
from arm.config import ArmConfig
from arm.kinematics import camera_ray
from arm.presets import PRESETS
from tests.arm.test_kinematics import MujocoCamera

CONFIG = ArmConfig()


def reachable_targets(n: int, seed: int = 3) -> list[np.ndarray]:
    return sample_reachable_targets(n, seed, CONFIG.kinematics, CONFIG.ik)


@pytest.fixture(scope="module")
def aim():
    return CameraAim(CONFIG.kinematics, CONFIG.ik)


@pytest.mark.slow
def test_reachable_targets_are_hit_within_2cm_and_inside_the_windows(aim):
    mj = MujocoCamera()
    targets = reachable_targets(40)
    solved = 0
    for t in targets:
        r = aim.aim(t)
        assert r.ok, (t, r.reason)
        assert limits.within(r.q)
        p, d = mj.ray(r.q)  # judged by MuJoCo's camera, not by our own kinematics
        v = t - p
        along = v @ d
        assert along > 0
        assert np.linalg.norm(v - along * d) < 0.02
        assert d[2] <= -np.sin(CONFIG.ik.min_look_down) + 1e-6  # from above
        solved += 1
    assert solved == len(targets)


def test_a_bloom_near_the_inspect_view_stays_near_inspect(aim):
    p, d = camera_ray(PRESETS["inspect"], CONFIG.kinematics)
    on_axis = p + 0.25 * d
    r = aim.aim(on_axis)
    assert r.ok and np.allclose(r.q, PRESETS["inspect"], atol=1e-3)
    r = aim.aim(on_axis + [0.0, 0.06, -0.03])  # off to the left and lower
    assert r.ok and r.q[0] > 0.05 and np.abs(r.q - PRESETS["inspect"]).max() < 0.4


@pytest.mark.parametrize("target, why", [
    ((2.0, 0.0, 0.2), "beyond reach"),  # 2 m away
    ((0.3, 0.0, 0.8), "unreachable"),  # above the camera: cannot be seen from above
    ((0.3, 0.0, -0.1), "below the floor"),  # base_link is 5 cm above the floor
    ((0.1, 0.05, 0.05), "inside the robot's body"),
    ((-0.5, 0.0, 0.2), "unreachable"),  # behind the robot, over the deck
    ((0.06 + 0.4 * np.cos(np.radians(-88)), 0.4 * np.sin(np.radians(-88)), 0.2), "shoulder_pan window"),
    # bearing -88 deg: outside [-86, 90], and +92 deg (leaning back over the axis) is too
    ((0.3, np.nan, 0.2), "finite"),
])
def test_unreachable_targets_are_reported_not_clipped(aim, target, why):
    r = aim.aim(target)
    assert not r.ok and r.q is None and why in r.reason
