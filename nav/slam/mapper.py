"""The SLAM pipeline, one scan at a time: a table of contents of ``nav.slam``.

``process`` takes a lidar revolution and the wheel odometry pose it was taken at and

1. turns it into ``base_link`` points, dropping returns below 0.25 m (``scan_points``);
2. registers it against the local voxel map, wheel odometry giving the guess (``lidar_odometry``);
3. every ``keyframe_distance`` / ``keyframe_angle`` adds a pose-graph node joined to the last by
   the registered motion, looks for a revisit and, on an accepted loop match, optimises the
   graph and re-renders the grid from every scan at its corrected pose (``loop_closure``,
   ``pose_graph``);
4. renders the scan into the log-odds grid at its map pose (``grid``).

Frames: lidar odometry runs in its own smooth frame; the graph's optimised keyframes give the
correction from it to ``map``. ``map_to_odom`` is what the navigator needs: the map pose of the
latest scan composed with the inverse of the wheel odometry pose it was taken at (REP-105).
The map frame is the pose given at construction: the dock at start-up, and the last known map
pose of the dock after a map reset, so goals given in ``map`` stay valid across a reset.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hw.odometry import Pose2D
from nav.frames import compose, distance, inverse, transform_points, yaw_error
from nav.grid_geometry import GridGeometry
from nav.occupancy import OccupancyMap
from nav.slam.config import SlamConfig
from nav.slam.grid import LogOddsGrid
from nav.slam.lidar_odometry import LidarOdometry
from nav.slam.loop_closure import LoopCloser
from nav.slam.pose_graph import PoseGraph
from nav.slam.scan_points import scan_points

#: Inverse variances of a lidar-odometry edge between keyframes (x, y: (1 cm)^-2, yaw: (5 mrad)^-2).
ODOMETRY_INFORMATION = (1e4, 1e4, 4e4)
#: ... and of a loop-closure edge (2 cm, 10 mrad): a single match is trusted less than the chain.
LOOP_INFORMATION = (2.5e3, 2.5e3, 1e4)
#: Travel after an accepted loop closure before the next is looked for, m: one revisit closes
#: the loop; re-closing it every keyframe would only re-solve the same graph.
LOOP_GAP = 1.0
#: A loop match that moves the estimate less than this, m, confirms the graph: its edge is kept
#: but solving and re-rendering for sub-centimetre changes would cost ~0.1-0.5 s for nothing.
#: The grid is re-rendered only when the solve moved some keyframe by half a cell or more.
LOOP_SETTLED = 0.01
#: Scans kept for re-rendering are at least this far apart (m, rad): standing still adds nothing
#: to keep, and a robot that maps for hours keeps ~2 MB per 100 m driven (float16 points).
KEEP_SPACING = 0.05


@dataclass(frozen=True)
class _Scan:
    index: int
    """Which scan of the run it was (0, 1, ...)."""
    keyframe: int
    relative: Pose2D
    """The scan's pose as seen from its keyframe (lidar odometry frame)."""
    points: np.ndarray
    """float16 (N, 2) returns in ``base_link`` (4 mm at 8 m: a tenth of a map cell)."""


class Mapper:
    def __init__(self, cfg: SlamConfig, lidar_mount: Pose2D, start: Pose2D = Pose2D()):
        self.cfg = cfg
        self.mount = lidar_mount
        self.odometry = LidarOdometry(cfg, start)
        self.graph = PoseGraph()
        self.loops = LoopCloser(cfg)
        self.grid = LogOddsGrid(GridGeometry.covering(start.x - 1.0, start.y - 1.0, start.x + 1.0, start.y + 1.0,
                                                      cfg.resolution))  # it grows as the robot explores
        self.pose = start
        """The latest scan's ``base_link`` pose in ``map``."""
        self.map_to_odom = Pose2D()
        self.loop_closures = 0
        self.solves = 0
        """Pose-graph optimisations run (each after an accepted loop closure that moved things)."""
        self.kept_bytes = 0
        """Memory of the kept scans and the keyframes' points (what re-rendering needs)."""
        self.scans = 0
        self._kf_lo: list[Pose2D] = []
        self._kf_points: list[np.ndarray] = []
        self._travel: list[float] = []
        self._scans: list[_Scan] = []
        self._next_loop = 0.0

    def process(self, angles: np.ndarray, ranges: np.ndarray, odom: Pose2D) -> Pose2D:
        """Integrate one revolution; returns the robot's map pose."""
        cfg = self.cfg
        points = scan_points(angles, ranges, self.mount, cfg.min_range, cfg.max_range)
        lo = self.odometry.register(points, odom)
        if self._new_keyframe(lo):
            self._add_keyframe(lo, points)
        k = len(self._kf_lo) - 1
        self.pose = compose(self._correction(), lo)
        relative = compose(inverse(self._kf_lo[k]), lo)
        last = self._scans[-1] if self._scans else None
        if last is None or last.keyframe != k or distance(last.relative, relative) >= KEEP_SPACING \
                or yaw_error(last.relative, relative) >= KEEP_SPACING:
            self._scans.append(_Scan(self.scans, k, relative, points[:, :2].astype(np.float16)))
            self.kept_bytes += self._scans[-1].points.nbytes
        self._render(self.pose, points)
        self.map_to_odom = compose(self.pose, inverse(odom))
        self.scans += 1
        return self.pose

    def occupancy(self) -> OccupancyMap:
        return self.grid.occupancy()

    @property
    def keyframes(self) -> int:
        return len(self._kf_lo)

    def trajectory(self) -> tuple[np.ndarray, np.ndarray]:
        """(indices (N,), poses (N, 3)): the kept scans' numbers and their map poses at the
        graph's current estimate (after every loop closure so far)."""
        poses = [self._scan_pose(s) for s in self._scans]
        return (np.array([s.index for s in self._scans]), np.array([[p.x, p.y, p.yaw] for p in poses]))

    # -- the pieces ----------------------------------------------------------------------------

    def _new_keyframe(self, lo: Pose2D) -> bool:
        if not self._kf_lo:
            return True
        last = self._kf_lo[-1]
        return distance(last, lo) >= self.cfg.keyframe_distance or yaw_error(last, lo) >= self.cfg.keyframe_angle

    def _add_keyframe(self, lo: Pose2D, points: np.ndarray) -> None:
        if not self._kf_lo:
            self.graph.add_node(lo)
            self._travel.append(0.0)
        else:
            prev = self._kf_lo[-1]
            self.graph.add_node(compose(self._correction(), lo))
            k = len(self.graph) - 1
            self.graph.add_edge(k - 1, k, compose(inverse(prev), lo), ODOMETRY_INFORMATION)
            self._travel.append(self._travel[-1] + distance(prev, lo))
        self._kf_lo.append(lo)
        self._kf_points.append(points.astype(np.float32))
        self.kept_bytes += self._kf_points[-1].nbytes
        self._close_loop(len(self.graph) - 1)

    def _close_loop(self, k: int) -> None:
        travel = np.asarray(self._travel)
        if not self.cfg.loop_closure or travel[k] < self._next_loop:
            return
        candidate = self.loops.candidate(self.graph.poses, travel, k)
        if candidate is None:
            return
        match = self.loops.match(self.graph.poses, self._kf_points, candidate, k)
        if match is None:
            return
        self.graph.add_edge(candidate, k, match.relative, LOOP_INFORMATION)
        self.loop_closures += 1
        self._next_loop = travel[k] + LOOP_GAP
        if match.correction < LOOP_SETTLED:
            return
        before = self.graph.poses.copy()
        self.graph.optimize()
        self.solves += 1
        if np.hypot(*(self.graph.poses[:, :2] - before[:, :2]).T).max() >= self.cfg.resolution / 2:
            self._rerender()

    def _correction(self) -> Pose2D:
        """lidar odometry frame -> map, from the latest keyframe's optimised pose."""
        return compose(self.graph.node(len(self.graph) - 1), inverse(self._kf_lo[-1]))

    def _scan_pose(self, s: _Scan) -> Pose2D:
        return compose(self.graph.node(s.keyframe), s.relative)

    def _render(self, pose: Pose2D, points: np.ndarray) -> None:
        sensor = compose(pose, self.mount)
        self.grid.integrate((sensor.x, sensor.y), transform_points(pose, points[:, :2]))

    def _rerender(self) -> None:
        """The grid again from every scan at its corrected pose (the map follows the graph)."""
        self.grid.clear()
        for s in self._scans:
            self._render(self._scan_pose(s), s.points.astype(np.float64))
