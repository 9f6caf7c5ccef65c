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

``delta`` hands out what each scan added (keyframes, edges, kept scans; every pose after a
solve) for the supervisor's checkpoint, and ``restored`` goes on from one (``checkpoint``).
"""
from __future__ import annotations

import numpy as np

from hw.odometry import Pose2D, wrap_angles
from nav.frames import compose, distance, inverse, transform_points, yaw_error
from nav.grid_geometry import GridGeometry
from nav.occupancy import OccupancyMap
from nav.slam.checkpoint import Checkpoint, Delta, KeptScan
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
#: to keep, and every cell a 12 m scan sees is seen by dozens of scans 0.2 m apart, so keeping
#: more only makes a re-render longer (~0.5 MB per 100 m driven, float16 points).
KEEP_SPACING = 0.2


def _place(keyframes: np.ndarray, relative: np.ndarray) -> np.ndarray:
    """(N, 2) map positions of scans at ``relative`` (x, y) from their keyframes' poses (N, 3)."""
    c, s = np.cos(keyframes[:, 2]), np.sin(keyframes[:, 2])
    return np.column_stack([keyframes[:, 0] + c * relative[:, 0] - s * relative[:, 1],
                            keyframes[:, 1] + s * relative[:, 0] + c * relative[:, 1]])


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
        self.rerendered = 0
        """Kept scans re-rendered after solves, all told (what loop closures cost the grid)."""
        self.kept_bytes = 0
        """Memory of the kept scans and the keyframes' points (what re-rendering needs)."""
        self.scans = 0
        self._kf_lo: list[Pose2D] = []
        self._kf_points: list[np.ndarray] = []
        self._travel: list[float] = []
        self._scans: list[KeptScan] = []
        self._next_loop = 0.0
        self._sent = (0, 0, 0, 0)
        """Graph nodes, edges, keyframes and kept scans already handed out in a ``delta``."""
        self._solved = False
        """Has the graph been solved since the last ``delta`` (its poses all moved)?"""

    @classmethod
    def restored(cls, cfg: SlamConfig, lidar_mount: Pose2D, checkpoint: Checkpoint, start: Pose2D) -> "Mapper":
        """A mapper that goes on from ``checkpoint`` (a lost worker's graph, kept scans and map)
        with the robot at ``start`` in ``map``: the graph's keyframes become this lidar
        odometry's keyframes as they stand (its frame is ``map``, the correction starts at
        identity), the grid is the checkpoint's map, and the local voxel map is seeded with the
        kept scans within its range, so the first scan registers against what was mapped here
        and takes out the odometry's drift through the gap."""
        m = cls(cfg, lidar_mount, start)
        m.graph.poses = checkpoint.poses.copy()
        m.graph.edges = list(checkpoint.edges)
        m._kf_lo = [m.graph.node(k) for k in range(len(m.graph))]
        m._kf_points = list(checkpoint.keyframe_points)
        m._travel = list(checkpoint.travel)
        m._scans = list(checkpoint.scans)
        m.scans, m.loop_closures, m.solves, m._next_loop = checkpoint.counters
        m.kept_bytes = sum(p.nbytes for p in m._kf_points) + sum(s.points.nbytes for s in m._scans)
        m.grid = LogOddsGrid.restored(checkpoint.occupancy)
        m._sent = (len(m.graph), len(m.graph.edges), len(m._kf_points), len(m._scans))
        near = [s for s in m._scans if distance(m._scan_pose(s), start) <= cfg.local_map_range]
        if near:
            m.odometry.seed(np.vstack([transform_points(m._scan_pose(s), s.points.astype(np.float64)) for s in near]))
        return m

    def delta(self) -> Delta:
        """What this mapper added since the last call: the checkpoint's share of a reply."""
        nodes, edges, kfs, scans = self._sent
        first = 0 if self._solved else nodes
        out = Delta(first, self.graph.poses[first:].copy(), tuple(self.graph.edges[edges:]),
                    tuple(self._kf_points[kfs:]), tuple(self._travel[kfs:]), tuple(self._scans[scans:]),
                    (self.scans, self.loop_closures, self.solves, self._next_loop),
                    self.occupancy() if self._solved else None)
        self._sent = (len(self.graph), len(self.graph.edges), len(self._kf_points), len(self._scans))
        self._solved = False
        return out

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
            kept = points[:, :2].astype(np.float16)
            reach = float(np.hypot(points[:, 0], points[:, 1]).max(initial=0.0)) + abs(self.mount.x) + 0.1
            self._scans.append(KeptScan(self.scans, k, relative, kept, reach))
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
        self._solved = True
        self._rerender(before)

    def _correction(self) -> Pose2D:
        """lidar odometry frame -> map, from the latest keyframe's optimised pose."""
        return compose(self.graph.node(len(self.graph) - 1), inverse(self._kf_lo[-1]))

    def _scan_pose(self, s: KeptScan) -> Pose2D:
        return compose(self.graph.node(s.keyframe), s.relative)

    def _render(self, pose: Pose2D, points: np.ndarray) -> None:
        sensor = compose(pose, self.mount)
        self.grid.integrate((sensor.x, sensor.y), transform_points(pose, points[:, :2]))

    def _rerender(self, before: np.ndarray) -> None:
        """The map follows the graph, where the solve moved it: the keyframes whose scans moved
        by half a cell or more anywhere within their reach (a turn of 0.01 rad moves a return
        12 m out by 12 cm) mark a region, their scans' reach at the old poses and the new; that
        region is cleared and re-rendered from every kept scan that touches it, each confined to
        it, so the cells outside keep what they had and nothing is counted twice."""
        if not self._scans:
            return
        kf = np.array([s.keyframe for s in self._scans])
        reach = np.array([s.reach for s in self._scans])
        shift = np.hypot(*(self.graph.poses[:, :2] - before[:, :2]).T)
        turn = np.abs(wrap_angles(self.graph.poses[:, 2] - before[:, 2]))
        moved = (shift[kf] + turn[kf] * reach) >= self.cfg.resolution / 2
        if not moved.any():
            return
        rel = np.array([[s.relative.x, s.relative.y] for s in self._scans])
        now_xy, was_xy = (_place(p[kf], rel) for p in (self.graph.poses, before))
        corners = np.vstack([xy[moved] + sign * reach[moved, None] for xy in (now_xy, was_xy) for sign in (-1, 1)])
        (x0, y0), (x1, y1) = corners.min(axis=0), corners.max(axis=0)
        g = self.grid.geometry
        (ix0, ix1), (iy0, iy1) = g.cell_of([x0, x1], [y0, y1])
        window = (int(ix0), int(iy0), int(ix1) + 1, int(iy1) + 1)
        self.grid.clear(window)
        touches = ((now_xy[:, 0] + reach >= x0) & (now_xy[:, 0] - reach <= x1) &
                   (now_xy[:, 1] + reach >= y0) & (now_xy[:, 1] - reach <= y1))
        self.rerendered += int(touches.sum())
        for i in np.flatnonzero(touches):
            s = self._scans[i]
            pose = self._scan_pose(s)
            sensor = compose(pose, self.mount)
            self.grid.integrate((sensor.x, sensor.y), transform_points(pose, s.points.astype(np.float64)), window)
