"""The collision monitor (hw/collision_monitor.py) on synthetic scans: each zone inside, outside
and on its edge, the approach mode's time to collision, a twist away from an obstacle left
alone, a stale scan, the lidar mount, and every mux source held by it below the e-stop."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hw.collision_monitor import APPROACH, BLIND, NONE, SLOWDOWN, STOP, CollisionMonitor
from hw.config import CollisionMonitorConfig, HwConfig
from hw.interfaces import LidarScan, Twist
from tests.fixtures import make_base_rig

RADIUS = 0.22
MOUNT = (0.115, 0.0, 0.0)
WALLS = 3.0
"""The greenhouse around every synthetic scan, m: far beyond every zone, and a scan with no
valid return is blind, not clear."""


class ScanSource:
    """A lidar that returns the scan it was last given."""

    def __init__(self):
        self.scan: LidarScan | None = None

    def latest_scan(self) -> LidarScan | None:
        return self.scan

    def show(self, base_points, stamp: float, background: float = WALLS) -> None:
        """A scan whose returns land on ``base_points`` (base frame), the rest on a ring of
        walls ``background`` m from the lidar (inf: nothing there at all)."""
        p = np.asarray(base_points, dtype=float).reshape(-1, 2) - MOUNT[:2]
        angles = np.linspace(-math.pi, math.pi, 720, endpoint=False, dtype=np.float32)
        ranges = np.full(720, background, dtype=np.float32)
        for x, y in p:
            k = int(np.argmin(np.abs(np.angle(np.exp(1j * (angles - math.atan2(y, x)))))))
            angles[k], ranges[k] = math.atan2(y, x), math.hypot(x, y)
        self.scan = LidarScan(stamp, angles, ranges)


def blob(x: float, y: float, n: int = 5, spread: float = 0.03) -> np.ndarray:
    """``n`` returns across a small body centred at (x, y), base frame."""
    return np.stack([np.full(n, x), y + np.linspace(-spread, spread, n)], axis=1)


def monitor(points=(), config: CollisionMonitorConfig | None = None):
    lidar = ScanSource()
    lidar.show(points if len(points) else np.empty((0, 2)), stamp=0.0)
    return CollisionMonitor(config or CollisionMonitorConfig(), lidar, RADIUS, MOUNT), lidar


def test_nothing_seen_nothing_changed():
    m, _ = monitor()
    assert m.filter(Twist(0.4, 0.1, 0.3), 0.05) == Twist(0.4, 0.1, 0.3)
    assert m.verdict.action == NONE


def test_an_obstacle_in_the_stop_zone_stops_driving_toward_it_but_not_turning():
    m, _ = monitor(blob(0.27, 0.0))
    assert m.filter(Twist(0.2, 0.0, 0.5), 0.05) == Twist(0.0, 0.0, 0.5)
    assert m.verdict.action == STOP and m.verdict.holding
    assert m.verdict.nearest == pytest.approx(0.27, abs=0.01)


@pytest.mark.parametrize("twist", [Twist(-0.3, 0.0, 0.0), Twist(0.0, 0.3, 0.0), Twist(0.0, -0.3, 0.2)])
def test_a_twist_away_from_or_past_the_obstacle_stays_allowed(twist):
    m, _ = monitor(blob(0.27, 0.0))
    assert m.filter(twist, 0.05) == twist
    assert m.verdict.action == NONE


def test_sideways_the_zone_turns_with_the_direction_of_travel():
    m, _ = monitor(blob(0.0, 0.27))  # on the left
    assert m.filter(Twist(0.0, 0.2, 0.0), 0.05) == Twist(0.0, 0.0, 0.0)
    assert m.filter(Twist(0.2, 0.0, 0.0), 0.05) == Twist(0.2, 0.0, 0.0)


@pytest.mark.parametrize("along, stopped", [(0.2995, True), (0.3005, False)])
def test_the_stop_zone_edge_ahead(along, stopped):
    m, _ = monitor(blob(along, 0.0, spread=0.01))
    out = m.filter(Twist(0.05, 0.0, 0.0), 0.05)
    assert (out.vx == 0.0) is stopped


@pytest.mark.parametrize("across, stopped", [(0.125, True), (0.14, False)])
def test_the_stop_zone_edge_to_the_side(across, stopped):
    """Just ahead of the chassis the zone is as wide as the chassis (0.26 m), not the 0.22 m
    circle: something 1 cm beside the path of its side is passed by."""
    m, _ = monitor(np.stack([np.linspace(0.20, 0.24, 5), np.full(5, across)], axis=1))
    assert (m.filter(Twist(0.05, 0.0, 0.0), 0.05).vx == 0.0) is stopped


def test_a_point_diagonally_ahead_that_the_footprint_passes_by_does_not_stop_it():
    """(0.28, 0.18): inside the 0.30 x 0.22 box, but 0.27 m from where the footprint's centre
    gets in 8 cm, so going straight it passes 5 cm clear (the approach mode slows for it)."""
    m, _ = monitor(np.stack([np.full(5, 0.28), np.linspace(0.17, 0.19, 5)], axis=1))
    out = m.filter(Twist(0.1, 0.0, 0.0), 0.05)
    assert m.verdict.action != STOP and out.vx > 0.0


def test_fewer_than_min_points_is_noise():
    m, _ = monitor(blob(0.27, 0.0, n=2))
    assert m.filter(Twist(0.1, 0.0, 0.0), 0.05) == Twist(0.1, 0.0, 0.0)


def test_the_slowdown_zone_caps_the_speed_and_keeps_the_direction():
    m, _ = monitor(blob(0.55, 0.0))
    out = m.filter(Twist(0.3, 0.0, 0.2), 0.05)
    assert m.verdict.action == SLOWDOWN
    assert math.hypot(out.vx, out.vy) == pytest.approx(0.15)
    assert out.wz / out.vx == pytest.approx(0.2 / 0.3)  # scaled together, never turned
    slow = Twist(0.1, 0.0, 0.0)
    assert m.filter(slow, 0.1) == slow  # already slower than the cap


def test_pots_beside_an_aisle_do_not_slow_the_robot():
    aisle = np.concatenate([blob(x, side * 0.40) for x in (-0.5, 0.0, 0.5, 1.0) for side in (-1, 1)])
    m, _ = monitor(aisle)
    assert m.filter(Twist(0.4, 0.0, 0.0), 0.05) == Twist(0.4, 0.0, 0.0)


def test_approach_keeps_the_time_to_collision():
    """A wall 1.0 m ahead, the chassis' front 0.165 m ahead of the centre: at 0.5 m/s contact is
    1.67 s away (more than 1.2 s: untouched); at 1.0 m/s it is 0.835 s away, first touched at
    the 0.9 s step, so the twist is scaled to 0.9 / 1.2."""
    m, _ = monitor(blob(1.0, 0.0, n=9, spread=0.2))
    assert m.filter(Twist(0.5, 0.0, 0.0), 0.05) == Twist(0.5, 0.0, 0.0)
    out = m.filter(Twist(1.0, 0.0, 0.0), 0.1)
    assert m.verdict.action == APPROACH
    assert out.vx == pytest.approx(0.9 / 1.2)


def test_approach_follows_a_curving_twist():
    """Turning left at 0.5 m/s and 1 rad/s the base curves into a box ahead-left that a straight
    line would pass."""
    box = blob(0.45, 0.35, n=7, spread=0.08)
    m, _ = monitor(box)
    m.filter(Twist(0.5, 0.0, 0.0), 0.05)
    assert m.verdict.action == NONE
    out = m.filter(Twist(0.5, 0.0, 1.2), 0.05)
    assert m.verdict.action == APPROACH and 0.0 < out.vx < 0.5 and out.wz / out.vx == pytest.approx(1.2 / 0.5)


def test_a_stale_scan_stops_driving_not_turning():
    m, lidar = monitor()
    assert m.filter(Twist(0.2, 0.0, 0.0), 0.4) == Twist(0.2, 0.0, 0.0)
    assert m.filter(Twist(0.2, 0.0, 0.4), 0.6) == Twist(0.0, 0.0, 0.4)
    assert m.verdict.action == BLIND
    lidar.show(np.empty((0, 2)), stamp=0.6)
    assert m.filter(Twist(0.2, 0.0, 0.0), 0.7) == Twist(0.2, 0.0, 0.0)


def test_the_lidar_mount_is_applied():
    """A return 0.17 m in front of the lidar is 0.285 m in front of the base centre (with no
    mount it would be 0.17 m: inside the footprint, dropped as the robot's own body)."""
    m, lidar = monitor()
    lidar.scan = LidarScan(0.0, np.zeros(5, dtype=np.float32) + np.linspace(-0.05, 0.05, 5, dtype=np.float32),
                           np.full(5, 0.17, dtype=np.float32))
    m.filter(Twist(0.1, 0.0, 0.0), 0.05)
    assert m.points[:, 0] == pytest.approx(0.115 + 0.17 * np.cos(np.linspace(-0.05, 0.05, 5)), abs=1e-6)
    assert m.verdict.action == STOP


def test_disabled_passes_everything():
    m, _ = monitor(blob(0.25, 0.0), CollisionMonitorConfig(enabled=False))
    assert m.filter(Twist(0.3, 0.0, 0.0), 0.05) == Twist(0.3, 0.0, 0.0)


@pytest.mark.parametrize("source", ["joy", "manual", "auto"])
def test_every_mux_source_is_held_below_the_estop(source):
    rig = make_base_rig(HwConfig())
    lidar = ScanSource()
    rig.base.guard = CollisionMonitor(CollisionMonitorConfig(), lidar, RADIUS, MOUNT)
    lidar.show(blob(0.27, 0.0), stamp=0.0)
    rig.mux.publish(source, Twist(0.3, 0.0, 0.0), 0.0)
    rig.base.tick(0.0)
    assert rig.base.source == source
    assert rig.base.command == Twist(0.0, 0.0, 0.0)
    lidar.show(blob(0.27, 0.0, n=0), stamp=0.1)  # the person stepped away
    rig.mux.publish(source, Twist(0.3, 0.0, 0.0), 0.1)
    rig.base.tick(0.1)
    assert rig.base.command == Twist(0.3, 0.0, 0.0)
    rig.button.level = rig.config.estop.engaged_level  # the e-stop is above it: zero, whatever it says
    rig.base.tick(0.2)
    assert rig.base.command == Twist(0.0, 0.0, 0.0) and rig.base.source == "estop"


def test_the_chassis_own_returns_are_not_obstacles():
    m, _ = monitor(blob(0.06, 0.0))  # the shoulder brackets the lidar sees behind it in every pose
    assert m.filter(Twist(0.3, 0.0, 0.0), 0.05) == Twist(0.3, 0.0, 0.0)
    assert np.hypot(m.points[:, 0], m.points[:, 1]).min() > 2.0  # only the walls are left


# -- blind is not clear ----------------------------------------------------------------------

def test_a_blind_scan_stops_driving_on_the_tick_it_arrives_and_the_drive_resumes_when_it_sees():
    m, lidar = monitor()
    assert m.filter(Twist(0.4, 0.0, 0.3), 0.05) == Twist(0.4, 0.0, 0.3)
    assert m.fault is None and m.untrusted_since is None
    lidar.show(np.empty((0, 2)), stamp=0.1, background=math.inf)  # covered: on time, every return inf
    assert m.filter(Twist(0.4, 0.0, 0.3), 0.1) == Twist(0.0, 0.0, 0.3)
    assert m.verdict.action == BLIND and m.fault == "lidar_blind" and m.untrusted_since == 0.1
    lidar.show(np.empty((0, 2)), stamp=0.2, background=math.inf)
    m.filter(Twist(0.4, 0.0, 0.0), 0.2)
    assert m.untrusted_since == 0.1  # since when, not since the last scan
    lidar.show(np.empty((0, 2)), stamp=0.3)
    assert m.filter(Twist(0.4, 0.0, 0.0), 0.3) == Twist(0.4, 0.0, 0.0)
    assert m.fault is None and m.untrusted_since is None


def test_untrusted_since_covers_a_stale_scan_too():
    m, _ = monitor()
    m.check(0.4)
    assert m.untrusted_since is None
    m.check(0.6)
    assert m.fault == "lidar_stale" and m.untrusted_since == pytest.approx(0.5)  # the last scan + 0.5 s


def test_an_all_inf_scan_is_blind_with_the_monitor_off_too():
    """``untrusted_since`` is for the mission's own pause: it does not depend on the monitor acting."""
    m, lidar = monitor(config=CollisionMonitorConfig(enabled=False))
    lidar.show(np.empty((0, 2)), stamp=0.1, background=math.inf)
    assert m.filter(Twist(0.3, 0.0, 0.0), 0.1) == Twist(0.3, 0.0, 0.0)
    assert m.fault == "lidar_blind" and m.untrusted_since == 0.1


# -- the outline: the chassis and the arm as it stands ------------------------------------------

INSPECT = (0.0, -0.40, 0.90, -0.80)
TUCK = (0.0, -1.40, 1.40, 0.0)


def arm_at(q):
    from arm.config import KinematicsConfig
    from arm.outline import arm_capsules

    return lambda: arm_capsules(q, KinematicsConfig())


def test_a_leg_6_cm_beside_the_chassis_is_seen_and_stops_a_strafe_into_it():
    leg = np.stack([np.linspace(-0.03, 0.03, 5), np.full(5, 0.13 + 0.06)], axis=1)
    m, _ = monitor(leg)
    assert m.filter(Twist(0.0, 0.2, 0.0), 0.05) == Twist(0.0, 0.0, 0.0)
    assert m.verdict.action == STOP and len(m.points) > 700  # the leg's returns are kept
    out = m.filter(Twist(0.2, 0.0, 0.0), 0.05)  # driving past it, 6 cm clear: slowed, not stopped
    assert m.verdict.action != STOP and out.vx > 0.0


def test_the_arms_own_returns_are_not_obstacles():
    """At ``tuck`` the forearm hangs in front of the lidar (model README): its returns are the
    robot's own, while the same returns with the arm at ``home`` stop the base."""
    forearm = blob(0.22, 0.0, spread=0.01)
    lidar = ScanSource()
    lidar.show(forearm, stamp=0.0)
    m = CollisionMonitor(CollisionMonitorConfig(), lidar, RADIUS, MOUNT, arm=arm_at(TUCK))
    assert m.filter(Twist(0.3, 0.0, 0.0), 0.05) == Twist(0.3, 0.0, 0.0)
    bare = CollisionMonitor(CollisionMonitorConfig(), lidar, RADIUS, MOUNT)
    assert bare.filter(Twist(0.3, 0.0, 0.0), 0.05) == Twist(0.0, 0.0, 0.0)


def test_a_turn_that_swings_the_arm_into_a_return_is_limited():
    """The arm out at ``inspect`` reaches 0.34 m ahead; a post at (0.30, 0.10) beside it is
    hit turning left, not turning right, and not at all without the arm."""
    post = blob(0.30, 0.10, spread=0.01)
    lidar = ScanSource()
    lidar.show(post, stamp=0.0)
    m = CollisionMonitor(CollisionMonitorConfig(), lidar, RADIUS, MOUNT, arm=arm_at(INSPECT))
    left = m.filter(Twist(0.0, 0.0, 0.8), 0.05)
    assert m.verdict.action in (STOP, APPROACH) and 0.0 <= left.wz < 0.8
    assert m.filter(Twist(0.0, 0.0, -0.8), 0.05) == Twist(0.0, 0.0, -0.8)
    bare = CollisionMonitor(CollisionMonitorConfig(), lidar, RADIUS, MOUNT)
    assert bare.filter(Twist(0.0, 0.0, 0.8), 0.05) == Twist(0.0, 0.0, 0.8)


def test_a_turn_that_hits_within_its_first_step_is_zeroed():
    """With the arm out a post 6 cm beside the gripper is 0.6 cm from it after 0.1 s of a
    1 rad/s left turn: no turn at all (the whole twist stopped, a holding verdict)."""
    lidar = ScanSource()
    lidar.show(blob(0.32, 0.06, spread=0.005), stamp=0.0)
    m = CollisionMonitor(CollisionMonitorConfig(), lidar, RADIUS, MOUNT, arm=arm_at(INSPECT))
    assert m.filter(Twist(0.0, 0.0, 1.0), 0.05) == Twist(0.0, 0.0, 0.0)
    assert m.verdict.action == STOP and m.verdict.turn == 0.0 and m.verdict.holding
