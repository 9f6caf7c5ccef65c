"""AMCL on a synthetic greenhouse: the Omni motion model's statistics, the likelihood field,
the filter converging from 0.5 m / 0.3 rad off (driving and parked) and not claiming it early,
``map -> odom`` and determinism.

The map: a 7 x 4 m room, walls all round, 12 pots (r 0.1 m) in 3 rows 1 m apart, 0.05 m cells,
its origin placed so that the map frame's origin (the dock) is at (1.0, 0.5) in the room, in
the aisle between the south wall and the first row. Scans are ray-marched through the grid
(500 beams, 0.01 m range noise, seeded), from the true pose.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from nav.amcl.config import AmclConfig
from nav.amcl.likelihood_field import LikelihoodField
from nav.amcl.localisation import AmclLocalisation
from nav.amcl.motion_model import sample_motion
from nav.amcl.particle_filter import ParticleFilter
from nav.frames import compose, distance, yaw_error
from nav.occupancy import OccupancyMap
from tests.nav.builders import RES, covered, greenhouse_occupancy, scan_from_occupancy

MOUNT = Pose2D(0.115, 0.0, 0.0)
ORIGIN = (-1.0, -0.5)  # the room's south-west corner, in the map frame
OCC = OccupancyMap(greenhouse_occupancy(), RES, *ORIGIN)


def scan_at(pose: Pose2D, rng: np.random.Generator, stamp: float = 0.0) -> LidarScan:
    """A 500-beam revolution from ``pose`` (base_link in the map frame), 0.01 m range noise."""
    lidar = compose(pose, MOUNT)
    s = scan_from_occupancy(OCC.occupancy, RES, (lidar.x, lidar.y, lidar.yaw), beams=500, origin=ORIGIN)
    return LidarScan(stamp, s.angles, (s.ranges + rng.normal(0.0, 0.01, s.ranges.shape)).astype(np.float32))


def tup(p: Pose2D) -> tuple[float, float, float]:
    return p.x, p.y, p.yaw


# -- the motion model --------------------------------------------------------------------------

def test_the_omni_model_samples_the_step_in_each_particles_heading_with_nav2s_variances():
    alphas = (0.1, 0.2, 0.3, 0.4, 0.5)  # distinct, so a swapped term shows
    a, b = Pose2D(2.0, 1.0, 0.3), Pose2D(2.0 + 0.5 * math.cos(0.3 + 0.6), 1.0 + 0.5 * math.sin(0.3 + 0.6), 0.8)
    d, r = 0.5, 0.5  # 0.5 m at 0.6 rad left of the heading, turning 0.5 rad
    p = np.zeros((200_000, 3))
    p[:, 2] = math.pi / 2  # the particles face north, odometry's robot faces 0.3 rad
    out = sample_motion(p.copy(), a, b, alphas, np.random.default_rng(1))
    bearing = math.pi / 2 + 0.6
    u, v = np.array([math.cos(bearing), math.sin(bearing)]), np.array([math.sin(bearing), -math.cos(bearing)])
    trans, strafe = out[:, :2] @ u, out[:, :2] @ v
    rot = np.remainder(out[:, 2] - math.pi / 2 + math.pi, 2 * math.pi) - math.pi
    assert trans.mean() == pytest.approx(d, abs=0.005)
    assert strafe.mean() == pytest.approx(0.0, abs=0.005)
    assert rot.mean() == pytest.approx(r, abs=0.005)
    assert trans.var() == pytest.approx(0.3 * d * d + 0.4 * r * r, rel=0.03)  # alpha3 d^2 + alpha4 r^2
    assert rot.var() == pytest.approx(0.1 * r * r + 0.2 * d * d, rel=0.03)  # alpha1 r^2 + alpha2 d^2
    assert strafe.var() == pytest.approx(0.4 * r * r + 0.5 * d * d, rel=0.03)  # alpha4 r^2 + alpha5 d^2


def test_without_noise_a_sideways_step_is_replayed_as_a_strafe_in_the_particles_frame():
    p = np.array([[1.0, 1.0, math.pi / 2]])
    sample_motion(p, Pose2D(0.0, 0.0, 0.0), Pose2D(0.1, 0.2, 0.3), (0.0,) * 5, np.random.default_rng(0))
    # 0.1 m forward and 0.2 m left of a north-facing particle: 0.2 m west, 0.1 m north
    assert p[0] == pytest.approx([0.8, 1.1, math.pi / 2 + 0.3], abs=1e-12)


# -- the likelihood field ----------------------------------------------------------------------

def test_the_likelihood_field_is_zero_on_obstacles_grows_away_and_saturates():
    f = LikelihoodField(OCC, 2.0, 0.5, 0.5, 0.1, 12.0)
    assert np.all(f.distance[OCC.occupied()] == 0.0)
    pot = np.array([2.0, 1.0]) + ORIGIN  # a pot's centre, map frame
    pts = pot + np.array([[0.0, 0.0], [0.0, 0.2], [0.0, 0.3], [0.0, 0.4], [0.3, 0.45]])
    d = f.distance_at(pts)
    assert d[0] == 0.0 and 0.0 < d[1] < d[2] < d[3]
    ix, iy = OCC.geometry.cell_of(pts[:, 0], pts[:, 1])  # brute force: cell centre to nearest occupied centre
    cx, cy = OCC.geometry.centre_of(ix, iy)
    oy, ox = np.nonzero(OCC.occupied())
    ocx, ocy = OCC.geometry.centre_of(ox, oy)
    assert d == pytest.approx(np.hypot(cx[:, None] - ocx, cy[:, None] - ocy).min(axis=1), abs=1e-5)
    assert f.distance_at(np.array([-5.0, -5.0])) == 2.0  # off the map: the maximum
    lone = np.zeros((100, 100), np.int8)
    lone[0, 0] = 100
    far = LikelihoodField(OccupancyMap(lone, RES, 0.0, 0.0), 2.0, 0.5, 0.5, 0.1, 12.0)
    assert far.distance_at(np.array([[1.0, 0.0], [4.0, 4.0]])) == pytest.approx([1.0, 2.0], abs=1e-5)  # clipped


def test_unknown_cells_keep_their_distance_to_the_wall_as_in_nav2():
    occ = np.zeros((40, 40), np.int8)
    occ[:, 20] = 100  # a wall, unknown behind it as in a SLAM map
    occ[:, 21:] = -1
    f = LikelihoodField(OccupancyMap(occ, RES, 0.0, 0.0), 2.0, 0.5, 0.5, 0.1, 12.0)
    assert f.distance[10, 22] == pytest.approx(2 * RES)


def test_the_score_is_nav2s_sum_of_cubes_and_ranks_hits_over_misses_over_off_map():
    f = LikelihoodField(OCC, 2.0, 0.5, 0.5, 0.1, 12.0)
    pot = np.array([2.0, 1.0]) + ORIGIN
    pts = np.array([[pot] * 60, [pot + [0.0, 0.3]] * 60, [[-9.0, -9.0]] * 60])
    s = f.score(pts)
    assert s[0] == pytest.approx(math.log(1 + 60 * (0.5 + 0.5 / 12.0) ** 3))
    assert s[0] > s[1] > s[2]
    assert s[2] == pytest.approx(math.log(1 + 60 * (0.5 * math.exp(-4 / 0.02) + 0.5 / 12.0) ** 3))


# -- the filter --------------------------------------------------------------------------------

def drive(error, rng_seed=3, ticks=150):
    """Drive 4.5 m east along the aisle at 0.3 m/s; the wheels claim 2 % more and turn
    0.01 rad/m. Returns the per-tick (ready, map-pose xy error, yaw error)."""
    rng = np.random.default_rng(rng_seed)
    state = {"truth": Pose2D(), "odom": Pose2D(), "t": 0.0}
    loc = AmclLocalisation(AmclConfig(initial_pose=error), OCC, MOUNT, lambda: state["odom"],
                           lambda: scan_at(state["truth"], rng, state["t"]))
    trace = [(loc.ready(), *errors(loc, state))]
    for k in range(1, ticks + 1):
        s = 0.03 * k
        state.update(truth=Pose2D(s, 0.0, 0.0), odom=Pose2D(s * 1.02, 0.0, 0.01 * s), t=0.1 * k)
        loc.tick(state["t"])
        trace.append((loc.ready(), *errors(loc, state)))
    return loc, trace


def errors(loc, state):
    p = compose(loc.map_to_odom(), state["odom"])
    return distance(p, state["truth"]), yaw_error(p, state["truth"])


@pytest.mark.parametrize("error", [(0.4, 0.3, 0.3), (-0.3, -0.4, -0.3)])
def test_driving_along_the_aisle_it_converges_from_half_a_metre_and_0p3_rad_and_says_so_only_then(error):
    loc, trace = drive(error)
    ready = [r for r, _, _ in trace]
    assert trace[0][1] == pytest.approx(0.5) and not ready[0]  # before any scan: the configured pose
    assert not ready[1]  # one scan in, still unsure
    first = ready.index(True)  # converged on the way ...
    assert trace[first][1] < 0.05 and trace[first][2] < 0.05, trace[first]  # ... and right when it says so
    assert all(ready[first:])
    tail = np.array([(xy, yaw) for _, xy, yaw in trace[first:]])
    assert tail[:, 0].max() < 0.05 and tail[:, 1].max() < 0.05, tail.max(axis=0)  # and right all the way
    assert loc.filter.scans >= 4.5 / 0.06  # updated every 5 cm of travel (6 cm: 2 ticks), not every 0.25 m
    assert trace[-1][1] < 0.09 / 2 and trace[-1][2] < 0.045 / 2  # odometry alone: 9 cm, 0.045 rad off


def test_parked_it_converges_before_moving_then_updates_only_on_motion():
    rng, truth = np.random.default_rng(4), Pose2D()
    pf = ParticleFilter(AmclConfig(initial_pose=(0.5, 0.0, 0.3)), OCC, MOUNT)
    n = 0
    while not pf.converged and n < 60:
        assert pf.update(Pose2D(), scan_at(truth, rng))
        n += 1
    assert pf.converged and n <= 60
    est = pf.estimate()
    assert distance(est, truth) < 0.05 and yaw_error(est, truth) < 0.05, (n, est)
    assert not pf.update(Pose2D(), scan_at(truth, rng))  # parked: nothing new
    assert not pf.update(Pose2D(0.04, 0.0, 0.04), scan_at(Pose2D(0.04, 0.0, 0.04), rng))  # under the gates
    assert pf.update(Pose2D(0.06, 0.0, 0.0), scan_at(Pose2D(0.06, 0.0, 0.0), rng))  # past update_min_d
    assert pf.update(Pose2D(0.06, 0.0, 0.06), scan_at(Pose2D(0.06, 0.0, 0.06), rng))  # past update_min_a


def test_a_tight_but_wrong_cloud_is_not_ready_until_it_has_slid_onto_the_truth():
    """A cloud placed tight 0.3 m off: its spread passes from the start, but it is sliding."""
    rng = np.random.default_rng(5)
    pf = ParticleFilter(AmclConfig(initial_pose=(0.3, 0.0, 0.0), initial_cov=(0.02 ** 2, 0.02 ** 2, 0.01 ** 2)),
                        OCC, MOUNT)
    tight_but_wrong = 0
    for _ in range(80):
        pf.update(Pose2D(), scan_at(Pose2D(), rng))
        xy, yaw = pf.spread()
        err = distance(pf.estimate(), Pose2D())
        tight_but_wrong += xy < pf.config.converged_std[0] and yaw < pf.config.converged_std[1] and err > 0.1
        if pf.converged:
            break
    assert tight_but_wrong >= 10  # the spread alone would have called it converged, 0.1 m+ off
    assert pf.converged and err < 0.05, err


def test_lidar_returns_on_the_arm_and_past_max_range_are_dropped():
    truth, rng = Pose2D(), np.random.default_rng(6)
    scan = scan_at(truth, rng)
    seen, dropped, near = scan.ranges.copy(), scan.ranges.copy(), scan.ranges.copy()
    seen[100:160] = 0.2  # the arm, 0.2 m from the lidar
    seen[300:340] = 12.0  # at max range
    dropped[100:160] = dropped[300:340] = np.inf
    near[100:160] = 0.3  # just past laser_min_range: a real return
    runs = []
    for ranges in (seen, dropped, near):
        pf = ParticleFilter(AmclConfig(), OCC, MOUNT)
        pf.update(Pose2D(), LidarScan(0.0, scan.angles, ranges))
        runs.append(pf.particles)
    assert np.array_equal(runs[0], runs[1])  # as good as no return at all
    assert not np.array_equal(runs[1], runs[2])
    angles, ranges = ParticleFilter(AmclConfig(), OCC, MOUNT).beams(LidarScan(0.0, scan.angles, seen))
    assert len(ranges) == 60 and ranges.min() >= 0.25 and ranges.max() < 12.0


def test_estimate_is_a_circular_mean_and_spread_is_the_widest_axis():
    pf = ParticleFilter(AmclConfig(particles=100), OCC, MOUNT)
    pf.particles = np.column_stack([np.tile([-0.1, 0.1], 50), np.zeros(100), np.tile([math.pi - 0.1, -math.pi + 0.1], 50)])
    pf.log_weights = np.zeros(100)
    est = pf.estimate()
    assert abs(abs(est.yaw) - math.pi) < 1e-9 and est.x == pytest.approx(0.0, abs=1e-12)
    assert pf.spread() == pytest.approx((0.1, 0.1), abs=1e-9)


def test_random_particle_recovery_when_its_alphas_are_set():
    def kidnapped(slow, fast):
        rng = np.random.default_rng(7)
        pf = ParticleFilter(AmclConfig(initial_cov=(1e-4, 1e-4, 1e-4), recovery_alpha_slow=slow,
                                       recovery_alpha_fast=fast), OCC, MOUNT)
        for _ in range(5):
            pf.update(Pose2D(), scan_at(Pose2D(), rng))
        for k in range(1, 6):  # the scans now come from 2 m east and 1 m north: kidnapped
            pf.update(Pose2D(0.1 * k, 0.0, 0.0), scan_at(Pose2D(2.0, 1.0, 0.0), rng))
        return np.hypot(pf.particles[:, 0], pf.particles[:, 1])

    assert kidnapped(0.0, 0.0).max() < 1.0  # off (Nav2's default): the cloud stays put
    assert (kidnapped(0.001, 0.1) > 1.0).sum() > 10  # on: random particles across the map


def test_resample_interval_lets_weights_multiply_between_resamplings():
    rng = np.random.default_rng(8)
    pf = ParticleFilter(AmclConfig(resample_interval=2), OCC, MOUNT)
    pf.update(Pose2D(), scan_at(Pose2D(), rng))
    assert np.ptp(pf.log_weights) > 0  # weighted, not resampled
    pf.update(Pose2D(), scan_at(Pose2D(), rng))
    assert np.ptp(pf.log_weights) == 0  # resampled


# -- the Localisation ------------------------------------------------------------------------

def test_map_to_odom_composes_with_odometry_to_the_estimate_and_is_held_between_updates():
    rng = np.random.default_rng(9)
    state = {"odom": Pose2D(0.3, -0.2, 0.1), "truth": Pose2D(), "t": 0.0}
    loc = AmclLocalisation(AmclConfig(initial_pose=(0.2, 0.1, 0.2)), OCC, MOUNT, lambda: state["odom"],
                           lambda: scan_at(state["truth"], rng, state["t"]))
    assert tup(compose(loc.map_to_odom(), state["odom"])) == pytest.approx((0.2, 0.1, 0.2))  # before a scan
    for k in range(1, 61):
        state["t"] = 0.1 * k
        loc.tick(state["t"])
    assert loc.ready()
    est, m2o = loc.filter.estimate(), loc.map_to_odom()
    mp = compose(m2o, state["odom"])
    assert (mp.x, mp.y, mp.yaw) == pytest.approx((est.x, est.y, est.yaw), abs=1e-9)
    scans = loc.filter.scans
    loc.tick(state["t"])  # the same scan again: not fed twice
    assert loc.filter.scans == scans
    # 3 cm of odometry (under update_min_d): map -> odom held, the map pose follows odometry
    state.update(odom=compose(state["odom"], Pose2D(0.03, 0.0, 0.0)), truth=Pose2D(0.03, 0.0, 0.0), t=6.1)
    loc.tick(state["t"])
    assert loc.map_to_odom() == m2o
    assert tup(compose(loc.map_to_odom(), state["odom"])) == pytest.approx(tup(compose(est, Pose2D(0.03, 0.0, 0.0))))
    loc.reset(Pose2D(1.0, 0.0, 0.5))  # RViz's 2D Pose Estimate
    assert not loc.ready()
    mp = compose(loc.map_to_odom(), state["odom"])
    assert (mp.x, mp.y, mp.yaw) == pytest.approx((1.0, 0.0, 0.5), abs=1e-9)
    assert loc.filter.spread()[0] > 0.3  # reseeded with the initial covariance


def test_a_blind_scan_is_not_fed_to_the_filter_and_the_pose_follows_odometry():
    """A cart pushed over the lidar: the front arc returns nothing, the cart's face a hand's
    width off fills the side; weighed, such scans pull the cloud off the truth."""
    rng = np.random.default_rng(5)
    state = {"odom": Pose2D(), "truth": Pose2D(), "t": 0.0, "covered": False}

    def scan():
        s = scan_at(state["truth"], rng, state["t"])
        if state["covered"]:
            s = LidarScan(s.stamp, s.angles, covered(s.angles, s.ranges).astype(np.float32))
        return s

    loc = AmclLocalisation(AmclConfig(initial_pose=(0.0, 0.0, 0.0)), OCC, MOUNT, lambda: state["odom"], scan)
    for k in range(1, 31):
        state["t"] = 0.1 * k
        loc.tick(state["t"])
    assert loc.ready()
    m2o, scans = loc.map_to_odom(), loc.filter.scans
    state["covered"] = True
    for k in range(31, 41):  # shoved along: the wheels and the truth move 0.1 m, 0.1 rad
        state.update(t=0.1 * k, odom=Pose2D(0.01 * (k - 30), 0.0, 0.01 * (k - 30)),
                     truth=Pose2D(0.01 * (k - 30), 0.0, 0.01 * (k - 30)))
        loc.tick(state["t"])
    assert loc.filter.scans == scans and loc.map_to_odom() == m2o
    state["covered"] = False  # seeing again: updated as before
    for k in range(41, 46):
        state["t"] = 0.1 * k
        loc.tick(state["t"])
    assert loc.filter.scans > scans
    p = compose(loc.map_to_odom(), state["odom"])
    assert distance(p, state["truth"]) < 0.05 and yaw_error(p, state["truth"]) < 0.05


def test_the_same_seed_repeats_a_run_and_another_seed_does_not():
    def run(seed):
        rng = np.random.default_rng(10)
        pf = ParticleFilter(AmclConfig(initial_pose=(0.3, 0.2, 0.2), seed=seed), OCC, MOUNT)
        for k in range(10):
            pf.update(Pose2D(0.05 * k, 0.0, 0.0), scan_at(Pose2D(0.05 * k, 0.0, 0.0), rng))
        return pf.particles

    a, b, c = run(0), run(0), run(1)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)
