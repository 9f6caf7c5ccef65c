import math

import numpy as np
import pytest

from arm import limits
from arm.presets import ARM_JOINTS, PRESETS


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_every_preset_is_inside_its_windows(name):
    q = PRESETS[name]
    assert limits.within(q)
    assert np.array_equal(limits.clamp_arm(q), np.array(q))


def test_windows_are_the_seed_table_in_radians():
    assert limits.JOINT_LIMITS_DEG == {"shoulder_pan": (-86.0, 90.0), "shoulder_lift": (-86.0, 85.0),
                                       "elbow": (-90.0, 90.0), "wrist": (-90.0, 88.0)}
    assert limits.JOINT_LIMITS["wrist"] == pytest.approx((-math.pi / 2, math.radians(88)))
    assert tuple(limits.LOWER) == tuple(limits.JOINT_LIMITS[j][0] for j in ARM_JOINTS)


@pytest.mark.parametrize("joint", ARM_JOINTS)
def test_clamping_at_each_edge(joint):
    lo, hi = limits.JOINT_LIMITS[joint]
    assert limits.clamp_joint(joint, lo - 0.3) == lo
    assert limits.clamp_joint(joint, hi + 0.3) == hi
    assert limits.clamp_joint(joint, lo) == lo and limits.clamp_joint(joint, hi) == hi
    inside = 0.5 * (lo + hi)
    assert limits.clamp_joint(joint, inside) == inside
    assert limits.clamp_joint(joint, lo + 1e-6) == pytest.approx(lo + 1e-6)
    i = ARM_JOINTS.index(joint)
    q = np.zeros(4)
    q[i] = hi + 1.0
    assert limits.clamp_arm(q)[i] == hi and not limits.within(q)
    q[i] = lo - 1.0
    assert limits.clamp_arm(q)[i] == lo


def test_gripper_clamps_to_the_urdf_range_and_unknown_joints_are_errors():
    assert limits.clamp_joint("gripper", 1.0) == 0.25
    assert limits.clamp_joint("gripper", -1.0) == -0.20
    with pytest.raises(KeyError, match="unknown arm joint"):
        limits.clamp_joint("elbo", 0.0)


@pytest.mark.parametrize("deg, rad", [(-30, -0.20), (0, 0.025), (30, 0.25), (-45, -0.20), (90, 0.25), (15, 0.1375)])
def test_gripper_mapping_and_inverted_sign(deg, rad):
    assert limits.gripper_deg_to_rad(deg) == pytest.approx(rad)


def test_gripper_open_is_minus_30_and_closed_plus_30():
    assert limits.GRIPPER_OPEN_DEG == -30 and limits.GRIPPER_CLOSED_DEG == 30
    # open maps to the wide-open end of the URDF range (-0.20), closed to +0.25 (sim model README)
    assert limits.gripper_deg_to_rad(limits.GRIPPER_OPEN_DEG) == limits.GRIPPER_LIMITS[0]
    assert limits.gripper_deg_to_rad(limits.GRIPPER_CLOSED_DEG) == limits.GRIPPER_LIMITS[1]
    assert limits.GRIPPER_RANGE_UNVERIFIED is True


@pytest.mark.parametrize("deg", [-30, -12.5, 0, 7, 30])
def test_gripper_round_trip(deg):
    assert limits.gripper_rad_to_deg(limits.gripper_deg_to_rad(deg)) == pytest.approx(deg)
