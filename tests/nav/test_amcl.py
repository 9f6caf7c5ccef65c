"""AMCL's pieces on a synthetic greenhouse map: the Omni motion model, the likelihood field,
and the filter converging from a wrong initial pose."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hw.odometry import Pose2D
from nav.amcl.config import AmclConfig
from nav.amcl.likelihood_field import LikelihoodField
from nav.amcl.localisation import AmclLocalisation
from nav.amcl.motion_model import sample_motion
from nav.amcl.particle_filter import ParticleFilter
from nav.frames import compose
from nav.occupancy import OccupancyMap
from tests.nav.builders import RES, greenhouse_occupancy, scan_from_occupancy

MOUNT = Pose2D(0.115, 0.0, 0.0)
OCC = OccupancyMap(greenhouse_occupancy(), RES, 0.0, 0.0)  # map frame = the room's corner here


def scan_at(pose: Pose2D):
    lidar = compose(pose, MOUNT)
    return scan_from_occupancy(OCC.occupancy, RES, (lidar.x, lidar.y, lidar.yaw))


def test_the_omni_model_moves_each_particle_in_its_own_heading_with_the_alphas_spread():
    rng = np.random.default_rng(1)
    p = np.zeros((20000, 3))
    p[:, 2] = math.pi / 2  # particles face north; odometry says 1 m east (its heading)
    sample_motion(p, Pose2D(0, 0, 0), Pose2D(1.0, 0.0, 0.0), (0.2,) * 5, rng)
    assert p[:, 1].mean() == pytest.approx(1.0, abs=0.02)  # forward in the particle's heading
    assert p[:, 0].mean() == pytest.approx(0.0, abs=0.02)
    assert p[:, 1].std() == pytest.approx(math.sqrt(0.2), rel=0.05)  # alpha3 * d^2
    assert p[:, 0].std() == pytest.approx(math.sqrt(0.2), rel=0.05)  # strafe: alpha5 * d^2
    assert p[:, 2].std() == pytest.approx(math.sqrt(0.2), rel=0.05)  # alpha4 * d^2


def test_a_sideways_step_is_a_strafe_not_noise():
    rng = np.random.default_rng(2)
    p = np.zeros((5000, 3))
    sample_motion(p, Pose2D(0, 0, 0), Pose2D(0.0, 0.1, 0.0), (0.0, 0.0, 0.0, 0.0, 0.0), rng)
    assert np.allclose(p, [0.0, 0.1, 0.0])


def test_the_likelihood_field_is_zero_on_obstacles_and_grows_away_from_them():
    f = LikelihoodField(OCC, 2.0, 0.5, 0.5, 0.08, 12.0)
    ix, iy = OCC.cell_of([2.0, 2.0, 2.0], [1.0, 1.3, 1.5])  # a pot's centre, 0.2 m and 0.4 m north of it
    d = f.distance[iy, ix]
    assert d[0] == 0.0 and 0.1 < d[1] < d[2] <= 0.45
    on = f.weights(np.array([[[2.0, 1.0]] * 10]))
    off = f.weights(np.array([[[2.0, 1.5]] * 10]))
    far = f.weights(np.array([[[-5.0, -5.0]] * 10]))  # off the map
    assert on[0] > off[0] > far[0] >= 1.0


@pytest.mark.parametrize("error", [(0.4, 0.3, 0.3), (-0.3, -0.4, -0.3), (0.5, 0.0, 0.3)])
def test_the_filter_converges_from_half_a_metre_and_0p3_rad_standing_still(error):
    truth = Pose2D(1.0, 0.5, 0.0)
    cfg = AmclConfig(initial_pose=(truth.x + error[0], truth.y + error[1], error[2]))
    pf = ParticleFilter(cfg, OCC, MOUNT)
    scan = scan_at(truth)
    assert not pf.settled
    for _ in range(60):
        pf.update(Pose2D(), scan)
        if pf.settled:
            break
    assert pf.settled
    est = pf.estimate()
    assert math.hypot(est.x - truth.x, est.y - truth.y) < 0.05 and abs(est.yaw) < 0.05


def test_converged_it_follows_a_drive_with_biased_odometry_and_updates_only_on_motion():
    truth, odom = Pose2D(1.0, 0.5, 0.0), Pose2D()
    pf = ParticleFilter(AmclConfig(initial_pose=(1.0, 0.5, 0.0), initial_std=(0.02, 0.02, 0.01), update_min_d=0.25),
                        OCC, MOUNT)
    for _ in range(10):
        pf.update(odom, scan_at(truth))
    assert pf.settled
    updated = 0
    for k in range(1, 61):  # 3 m east; the wheels claim 5 % more
        truth = Pose2D(1.0 + 0.05 * k, 0.5, 0.0)
        odom = Pose2D(0.05 * k * 1.05, 0.0, 0.0)
        if pf.update(odom, scan_at(truth)):
            updated += 1
            at_update = truth
    est = pf.estimate()  # the pose at the last update
    # odometry alone is 0.15 m off by the end; the cell-quantised synthetic scans and the
    # seed's wide alphas (a 0.25 m step spreads the cloud ~0.1 m) keep AMCL to a few cm
    assert math.hypot(est.x - at_update.x, est.y - at_update.y) < 0.08
    assert 10 <= updated <= 16  # every update_min_d of odometry (3.15 m / 0.25 m), not every scan


def test_map_to_odom_composes_to_the_estimate_and_runs_repeat_for_a_seed():
    def run():
        odom = {"pose": Pose2D(0.3, -0.2, 0.1)}
        loc = AmclLocalisation(AmclConfig(initial_pose=(1.3, 0.8, 0.2)), OCC, MOUNT, lambda: odom["pose"],
                               lambda: type(scan)(t["now"], scan.angles, scan.ranges))
        for k in range(30):
            t["now"] = 0.1 * k
            loc.tick(t["now"])
        return loc

    scan, t = scan_at(Pose2D(1.0, 0.5, 0.0)), {"now": 0.0}
    a, b = run(), run()
    assert a.ready()
    est = a.filter.estimate()
    mp = compose(a.map_to_odom(), Pose2D(0.3, -0.2, 0.1))
    assert (mp.x, mp.y, mp.yaw) == pytest.approx((est.x, est.y, est.yaw), abs=1e-9)
    assert np.array_equal(a.filter.particles, b.filter.particles)
