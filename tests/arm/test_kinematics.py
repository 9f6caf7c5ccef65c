"""The wrist camera's forward kinematics against MuJoCo's own camera pose on the robot model."""
import mujoco
import numpy as np
import pytest

from arm import limits
from arm.config import KinematicsConfig
from arm.kinematics import camera_ray, miss_distance
from arm.presets import ARM_JOINTS, PRESETS

SCENE = "sim/models/mirte_master/scene.xml"


class MujocoCamera:
    """The wrist camera's optical centre and axis in base_link, as MuJoCo computes them."""

    def __init__(self):
        self.m = mujoco.MjModel.from_xml_path(SCENE)
        self.d = mujoco.MjData(self.m)
        self.adr = [self.m.joint(j).qposadr[0] for j in ARM_JOINTS]
        self.cam = self.m.camera("wrist_camera").id
        self.base = self.m.body("base_link").id

    def ray(self, q):
        self.d.qpos[self.adr] = q
        mujoco.mj_forward(self.m, self.d)
        rot = self.d.xmat[self.base].reshape(3, 3)
        p = rot.T @ (self.d.cam_xpos[self.cam] - self.d.xpos[self.base])
        axis = rot.T @ -self.d.cam_xmat[self.cam].reshape(3, 3)[:, 2]  # cameras look along -z
        return p, axis


@pytest.fixture(scope="module")
def mj():
    return MujocoCamera()


@pytest.mark.slow
def test_fk_matches_mujoco_across_the_windows(mj):
    rng = np.random.default_rng(7)
    qs = [np.array(v) for v in PRESETS.values()] + list(rng.uniform(limits.LOWER, limits.UPPER, (40, 4)))
    for q in qs:
        p, d = camera_ray(q, KinematicsConfig())
        mp, md = mj.ray(q)
        assert np.allclose(p, mp, atol=1e-6), q
        assert np.allclose(d, md, atol=1e-5), q


def test_inspect_looks_forward_and_down_as_the_model_readme_says():
    p, d = camera_ray(PRESETS["inspect"], KinematicsConfig())
    assert p[0] == pytest.approx(0.31, abs=0.01) and p[2] + 0.051 == pytest.approx(0.455, abs=0.01)
    assert np.degrees(np.arcsin(-d[2])) == pytest.approx(53, abs=1)


def test_miss_distance():
    k = KinematicsConfig()
    q = PRESETS["inspect"]
    p, d = camera_ray(q, k)
    assert miss_distance(q, p + 0.3 * d, k) == pytest.approx((0.0, 0.3), abs=1e-12)
    side = np.cross(d, [0, 0, 1.0])
    side /= np.linalg.norm(side)
    assert miss_distance(q, p + 0.2 * d + 0.05 * side, k)[0] == pytest.approx(0.05)
    assert miss_distance(q, p - 0.2 * d, k)[0] == pytest.approx(0.2)  # behind the camera
