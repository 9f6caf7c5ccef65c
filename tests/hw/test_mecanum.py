import numpy as np
import pytest

from hw.config import BaseConfig
from hw.interfaces import WHEELS, Twist
from hw.mecanum import Mecanum

R, K = 0.051, 0.225


@pytest.fixture
def kin():
    return Mecanum.from_config(BaseConfig())


def test_from_config_uses_seed_geometry(kin):
    assert kin.wheel_radius == R and kin.lx_plus_ly == K


def test_known_numbers(kin):
    w = kin.inverse(Twist(0.3, 0.1, 0.5))
    expected = np.array(
        [(0.3 - 0.1 - K * 0.5) / R, (0.3 + 0.1 + K * 0.5) / R, (0.3 + 0.1 - K * 0.5) / R, (0.3 - 0.1 + K * 0.5) / R]
    )
    np.testing.assert_allclose(w, expected)
    # 0.255 m/s forward is exactly 5 rad/s on every wheel
    np.testing.assert_allclose(kin.inverse(Twist(0.255, 0, 0)), [5.0] * 4)


def test_pure_strafe_left_signs(kin):
    w = dict(zip(WHEELS, kin.inverse(Twist(0, 0.2, 0))))
    assert w["front_left"] < 0 and w["rear_right"] < 0
    assert w["front_right"] > 0 and w["rear_left"] > 0
    assert len({round(abs(v), 9) for v in w.values()}) == 1


def test_pure_ccw_rotation_signs(kin):
    w = dict(zip(WHEELS, kin.inverse(Twist(0, 0, 1.0))))
    assert w["front_left"] < 0 and w["rear_left"] < 0  # left side runs backwards
    assert w["front_right"] > 0 and w["rear_right"] > 0
    assert w["front_right"] == pytest.approx(K / R)


@pytest.mark.parametrize("twist", [Twist(0.3, -0.2, 0.7), Twist(-0.1, 0.0, -1.2), Twist(0, 0, 0), Twist(0.05, 0.4, 0)])
def test_round_trip(kin, twist):
    back = kin.forward(kin.inverse(twist))
    assert (back.vx, back.vy, back.wz) == pytest.approx((twist.vx, twist.vy, twist.wz), abs=1e-12)


def test_forward_known_numbers_and_least_squares(kin):
    # r/4 sums: vx = r/4 * sum, vy = r/4 * (-fl + fr + rl - rr), wz = r/(4k) * (-fl + fr - rl + rr)
    w = np.array([1.0, 2.0, 3.0, 4.0])
    t = kin.forward(w)
    assert t.vx == pytest.approx(R / 4 * 10)
    assert t.vy == pytest.approx(R / 4 * (-1 + 2 + 3 - 4))
    assert t.wz == pytest.approx(R / (4 * K) * (-1 + 2 - 3 + 4))


def test_forward_rejects_wrong_length(kin):
    with pytest.raises(ValueError):
        kin.forward([1.0, 2.0, 3.0])


def test_rejects_bad_geometry():
    with pytest.raises(ValueError):
        Mecanum(0.0, K)
