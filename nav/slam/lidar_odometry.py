"""Scan-to-map registration built from kiss-icp's components, with wheel odometry as the guess.

kiss-icp's own pipeline predicts each pose with a constant-velocity model; a robot that stops at
every pot and turns on the spot breaks that model, and in an aisle of repeated pots a bad guess
lets ICP slip one pot along (reference/upstream.md). Here the guess is the previous estimate
moved by the wheel odometry's delta since the last scan, and kiss-icp's adaptive threshold then
measures how far ICP had to correct that guess: with a good guess the correspondence gate
shrinks to centimetres and a pot can never pair with its neighbour 1 m away.

The pieces are kiss-icp's: the voxel hash map (local map around the robot), the point-to-point
registration with a robust kernel, and the adaptive threshold. The map and the registration are
kiss-icp's algorithm in the plane (``nav.slam.planar_icp``, the same poses to 1e-9): kiss-icp's
own looks up 27 voxels of a 3D map for every point and iteration, 18 of them empty for a 2D scan,
and registering the scan at half a voxel (below) made a scan cost 1.59 ms median and 2.60 ms p95
(CPU, the 180-pot patrol's 16,441 recorded scans, in one process beside the other variants),
against 1.21 / 1.87 ms thinned to 1.5 voxels; in the plane, 0.90 / 1.28 ms, the same trajectory
and map (the 180-pot survey's scans: 1.51 / 2.52 -> 0.79 / 1.19 ms, the same map). In the worker
over a live 180-pot patrol (``slam.scale``, the two patrols run side by side on a loaded machine)
2.26 / 3.28 -> 1.47 / 1.85 ms. It runs on one thread, so results do not depend on thread scheduling (runs are
deterministic for a seed).

What is registered is the scan as it goes into the local map, thinned to one return per half
voxel, not thinned again to one per 1.5 voxels as kiss-icp does. kiss-icp thins a 3D sweep of
~100k points; a 2D revolution has ~500 returns, and at 1.5 voxels (15 cm) about a hundred are
left. kiss-icp's thinning keeps the *first* return of each cell in beam order, so each kept
return sits towards the start of its cell in the direction the beam sweeps, all round the
robot: a rotation of the registered scan against the map. Every turn left the heading a few
milliradians short, never taken back (the local map agrees with itself; loop closures mend
disagreements between passes, not a map turned as a whole), and the whole map bent about the
dock: on the 180-pot greenhouse (issue 30, item 3) the heading was 3.5-5 mrad off from the
dock's first turn on and the east bay's walls were drawn 10-17 cm south. Replayed on the same
scans, the heading error after the first turn was (thinned to 1.5 / 1 / 0.5 voxels): a patrol
-3.4 / 0.1 / -0.1 mrad, a survey -4.0 / -3.8 / 0.2 mrad; so half a voxel, the map's own
thinning. On two recorded patrols, recall and precision against the world 0.90 / 0.92 and 0.75 /
0.80 became 0.995 / 1.00 at one voxel, trajectory error 0.087 -> 0.015 m and 0.087 -> 0.010 m.
"""
from __future__ import annotations

import numpy as np
from kiss_icp.config import KISSConfig
from kiss_icp.threshold import get_threshold_estimator
from kiss_icp.voxelization import voxel_down_sample

from hw.odometry import Pose2D
from nav.frames import compose, inverse, to_matrix
from nav.slam.config import SlamConfig
from nav.slam.planar_icp import VoxelMap, align
from nav.slam.relocate import WIDE, fitted, relocate


def kiss_config(cfg: SlamConfig) -> KISSConfig:
    """kiss-icp's config for 2D scans at greenhouse scale (a bare KISSConfig has no voxel size)."""
    kc = KISSConfig()
    kc.data.max_range = cfg.local_map_range
    kc.data.min_range = cfg.min_range
    kc.data.deskew = False
    kc.mapping.voxel_size = cfg.voxel_size
    kc.mapping.max_points_per_voxel = cfg.max_points_per_voxel
    kc.registration.max_num_threads = 1
    kc.adaptive_threshold.initial_threshold = cfg.initial_threshold
    kc.adaptive_threshold.min_motion_th = cfg.min_motion
    return kc


FIT = 0.7
"""Share of a scan's points within the local map's reach (at least ``FIT_POINTS`` of them) its
registered pose must put within a voxel of the local map, or the registration is not taken:
the robot is somewhere the guess and the correspondence gate cannot reach, so the scan is
searched for (``nav.slam.relocate``), and while no pose in reach fits it is coasted over, not
drawn. safety.people seed 106, 563.4-565.0 s: a cart that does not yield, its returns left out
as a person's pressing on the robot, shoved it 1.3 m in 1.6 s; registration followed at ~4 cm a
scan with 29-55 % of the points fitted, each scan went into the local map where it was wrongly
placed, and from then on the scans fitted that (98-100 %) a metre and 0.56 rad from the truth:
every goal after was boxed in by walls drawn across the robot, 21 pots failed and the robot
never got home. Over its 5,626 scans before the shove the least share fitted was 0.96 (p1 0.99)."""
FIT_POINTS = 30
"""Fewer points than this are too few to judge a fit by."""
WIDE_EVERY = 10
"""While lost, the wide window (``nav.slam.relocate.WIDE``, ~5x the near one's cost) is searched
every this many scans, the near one on every scan."""
GIVE_UP = 50
"""Scans lost after which the best pose found is taken as it is (5 s at the lidar's 10 Hz): a
greenhouse changed past recognition must not stop the map for good."""


class LidarOdometry:
    def __init__(self, cfg: SlamConfig, start: Pose2D = Pose2D()):
        kc = kiss_config(cfg)
        self._voxel = cfg.voxel_size
        self._reach = cfg.local_map_range
        self.local_map = VoxelMap(cfg.voxel_size, cfg.local_map_range, cfg.max_points_per_voxel)
        self.threshold = get_threshold_estimator(kc)
        self.pose = start
        """The latest registered pose of ``base_link`` in this odometry's frame."""
        self._odom: Pose2D | None = None
        self.lost = False
        """Was the last scan coasted over (too blind, hidden by people against the robot, or
        fitted nowhere in reach: ``FIT``)? Then the next one is searched for over a window
        (``nav.slam.relocate``): a cart over the lidar may have been shoving the robot."""
        self.relocations = 0
        """Scans searched for so far."""
        self.unfitted = 0
        """Scans no pose in reach fitted (``FIT``), coasted over so far."""
        self._lost_for = 0
        """Scans since the last one registered."""

    def seed(self, points: np.ndarray) -> None:
        """Fill the local map with (N, 2) points already placed in this odometry's frame (a
        restart's kept scans), thinned as a registered scan's are."""
        xyz = np.column_stack([points, np.zeros(len(points))])
        self.local_map.add(voxel_down_sample(xyz, self._voxel * 0.5))

    def register(self, points: np.ndarray, odom: Pose2D) -> Pose2D | None:
        """Register one scan's ``base_link`` points (N, 3); ``odom`` is the wheel odometry pose
        when it was taken. Returns the new pose, or None when no pose in reach fits the scan
        (``FIT``): it is then coasted over here (the pose is the guess), and not to be drawn."""
        guess = self._moved(odom)
        fine = voxel_down_sample(points, self._voxel * 0.5)
        if self.local_map.empty():
            new = guess
        else:
            sigma = self.threshold.get_threshold()
            new = None if self.lost else align(fine, self.local_map, guess, 3 * sigma, sigma)
            if new is not None and self._fits(fine, new):
                self.threshold.update_model_deviation(to_matrix(compose(inverse(guess), new)))
            else:  # a shove the wheels did not feel is no prediction error to learn from
                new = self._search(fine, guess, 3 * sigma, sigma)
            if new is None:  # coasted over, as ``coast`` would
                self.pose, self.lost = guess, True
                self._lost_for += 1
                self.unfitted += 1
                return None
        self.lost, self._lost_for = False, 0
        self.local_map.update(fine, new)
        self.pose = new
        return new

    def _fits(self, fine: np.ndarray, pose: Pose2D) -> bool:
        """Does ``pose`` put ``FIT`` of the scan's points within the local map's reach on it?
        (Beyond its reach the local map holds nothing to explain them by.)"""
        held = fine[np.hypot(fine[:, 0], fine[:, 1]) <= self._reach]
        return len(held) < FIT_POINTS or fitted(held, self.local_map, pose) >= FIT * len(held)

    def _search(self, fine: np.ndarray, guess: Pose2D, gate: float, kernel: float) -> Pose2D | None:
        """The scan's pose over the near window, or the wide one (every ``WIDE_EVERY`` scans
        lost), when one fits; the best found once lost ``GIVE_UP`` scans; else None."""
        self.relocations += 1
        found = relocate(fine, self.local_map, guess, gate, kernel)
        if self._fits(fine, found):
            return found
        if self._lost_for % WIDE_EVERY == 0:
            found = relocate(fine, self.local_map, guess, gate, kernel, WIDE)
            if self._fits(fine, found):
                return found
        return found if self._lost_for >= GIVE_UP else None

    def coast(self, odom: Pose2D) -> Pose2D:
        """Move the pose by the wheel odometry alone (a scan too blind to register): nothing
        joins the local map, and the adaptive threshold learns nothing from it."""
        self.pose = self._moved(odom)
        self.lost = True
        self._lost_for += 1
        return self.pose

    def _moved(self, odom: Pose2D) -> Pose2D:
        """The pose moved by the wheel odometry's delta since the last scan (the guess)."""
        delta = Pose2D() if self._odom is None else compose(inverse(self._odom), odom)
        self._odom = odom
        return compose(self.pose, delta)
