"""The SLAM pipeline, one scan at a time: a table of contents of ``nav.slam``.

``process`` takes a lidar revolution and the wheel odometry pose it was taken at and

1. turns it into ``base_link`` points, dropping returns below 0.25 m (``scan_points``); a scan
   too blind to trust (``hw.scan_trust``, the collision monitor's rule: a cart pushed over the
   lidar), or mostly on people against the robot (``HIDDEN``), is not registered, kept or drawn:
   the pose goes on by wheel odometry alone, and the next scan is searched for round it
   (``relocate``: whoever covered the lidar may have shoved the robot);
2. registers it against the local voxel map, wheel odometry giving the guess (``lidar_odometry``);
   a scan no pose in reach fits (a shove the wheels did not feel, past the correspondence gate)
   is searched for and, until one fits, coasted over as in 1;
3. every ``keyframe_distance`` / ``keyframe_angle`` adds a pose-graph node joined to the last by
   the registered motion, looks for a revisit and, on an accepted loop match, optimises the
   graph (``loop_closure``, ``pose_graph``) and starts re-rendering the region it moved from the
   kept scans at their corrected poses;
4. renders the scan into the log-odds grid at its map pose (``grid``), and draws a bounded share
   of a pending re-render apart, swapping it in once whole (``rerender``): a correction never
   stops the scan loop, and the map handed out is never half moved.

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
from hw.scan_trust import ScanTrust
from nav.frames import compose, distance, inverse, transform_points, yaw_error
from nav.grid_geometry import GridGeometry
from nav.occupancy import OccupancyMap
from nav.slam.checkpoint import Checkpoint, Delta, KeptScan
from nav.slam.config import SlamConfig
from nav.slam.grid import LogOddsGrid
from nav.slam.lidar_odometry import LidarOdometry
from nav.slam.loop_closure import LoopCloser
from nav.slam.pose_graph import PoseGraph
from nav.slam.rerender import BUDGET, Rerender, clipped, region_of, touching, union
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
#: A scan more than this share of whose returns lie on people against the robot is not registered:
#: what is left is too little to steer by (safety.people seed 104 at 658.4-665.3 s: 90-100 % of
#: the returns on a cart over the lidar, which slid the robot 0.64 m), and the next
#: one that is, is searched for (``nav.slam.relocate``: they may have been shoving the robot). A
#: person covering two thirds of the view leaves enough (``tests/nav/test_slam_people.py``).
HIDDEN = 0.8


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
        self.rerendering: Rerender | None = None
        """The region a solve moved, being drawn again apart from the live grid (None: none)."""
        self.swaps = 0
        """Re-renders swapped into the map whole."""
        self.kept_bytes = 0
        """Memory of the kept scans and the keyframes' points (what re-rendering needs)."""
        self.scans = 0
        self.trust = ScanTrust(cfg.blind)
        self.blind_scans = 0
        """Scans too blind to register, passed over on wheel odometry (``SlamConfig.blind``)."""
        self._kf_lo: list[Pose2D] = []
        self._kf_points: list[np.ndarray] = []
        self._travel: list[float] = []
        self._scans: list[KeptScan] = []
        self._next_loop = 0.0
        self._sent = (0, 0, 0, 0)
        """Graph nodes, edges, keyframes and kept scans already handed out in a ``delta``."""
        self._solved = False
        """Has the graph been solved since the last ``delta`` (its poses all moved)?"""
        self._swapped = False
        """Has a re-render been swapped into the map since the last ``delta``?"""

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
        if checkpoint.rerender is not None:  # the lost worker was drawing a correction: draw it again
            m._redraw(clipped(m.grid.geometry, checkpoint.rerender))
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
                    self.occupancy() if self._swapped else None,
                    self.rerendering.bounds if self.rerendering is not None else None)
        self._sent = (len(self.graph), len(self.graph.edges), len(self._kf_points), len(self._scans))
        self._solved = self._swapped = False
        return out

    def process(self, angles: np.ndarray, ranges: np.ndarray, odom: Pose2D,
                people: np.ndarray | None = None) -> Pose2D:
        """Integrate one revolution; returns the robot's map pose. ``people``: which returns
        fall on people (``nav.slam.people_mask``), left out once the scan is judged trustworthy."""
        cfg = self.cfg
        seen = np.isfinite(ranges)
        if self.trust.judge(angles, seen) is not None:
            return self._coast(odom)
        if people is not None:
            if np.count_nonzero(people) > HIDDEN * np.count_nonzero(seen):
                return self._coast(odom)
            ranges = np.where(people, np.inf, ranges)
        points = scan_points(angles, ranges, self.mount, cfg.min_range, cfg.max_range)
        lo = self.odometry.register(points, odom)
        if lo is None:  # no pose in reach fits it: somewhere the wheels did not take it
            return self._coasted(self.odometry.pose, odom)
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
            self._queue_kept()
        self._render(self.pose, points)
        return self._done(odom)

    def _coast(self, odom: Pose2D) -> Pose2D:
        """A blind scan (``SlamConfig.blind``), one mostly hidden by people against the robot
        (``HIDDEN``), or one no pose in reach fits (``nav.slam.lidar_odometry.FIT``): the pose
        moves by wheel odometry alone, and nothing of the scan is registered, kept or drawn; a
        pending re-render goes on. The next scan registered is searched for (``nav.slam.relocate``)."""
        return self._coasted(self.odometry.coast(odom), odom)

    def _coasted(self, lo: Pose2D, odom: Pose2D) -> Pose2D:
        """The map pose of a scan coasted over at ``lo`` (lidar odometry frame)."""
        self.pose = compose(self._correction(), lo)
        self.blind_scans += 1
        return self._done(odom)

    def _done(self, odom: Pose2D) -> Pose2D:
        """Every scan's end, blind or not: a share of a pending re-render, ``map_to_odom``."""
        self._rerender_step()
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
        region is drawn again from every kept scan that touches it, apart from the live grid and
        a share per scan (``nav.slam.rerender``); one still being drawn is widened to both."""
        if not self._scans:
            return
        kf = np.array([s.keyframe for s in self._scans])
        shift = np.hypot(*(self.graph.poses[:, :2] - before[:, :2]).T)
        turn = np.abs(wrap_angles(self.graph.poses[:, 2] - before[:, 2]))
        (now_xy, reach), (was_xy, _) = self._kept_at(self.graph.poses), self._kept_at(before)
        moved = (shift[kf] + turn[kf] * reach) >= self.cfg.resolution / 2
        if not moved.any():
            return
        region = region_of(self.grid.geometry, np.vstack([now_xy[moved], was_xy[moved]]), np.tile(reach[moved], 2))
        if region is not None and self.rerendering is not None:
            region = union(region, self.rerendering.region)
        self._redraw(region)

    def _kept_at(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N, 2) map positions of the kept scans were their keyframes at ``poses``, and their reach."""
        kf = np.array([s.keyframe for s in self._scans], dtype=int)
        rel = np.array([[s.relative.x, s.relative.y] for s in self._scans]).reshape(-1, 2)
        return _place(poses[kf], rel), np.array([s.reach for s in self._scans])

    def _redraw(self, region: GridGeometry | None) -> None:
        """Start drawing ``region`` again from every kept scan that touches it at its pose now."""
        if region is not None:
            xy, reach = self._kept_at(self.graph.poses)
            self.rerendering = Rerender(region, np.flatnonzero(touching(region, xy, reach)).tolist(), self.scans)

    def _queue_kept(self) -> None:
        """A scan kept while a re-render is pending is drawn into it too, after the older ones."""
        r, s = self.rerendering, self._scans[-1]
        if r is not None:
            p = self._scan_pose(s)
            if touching(r.region, np.array([[p.x, p.y]]), np.array([s.reach]))[0]:
                r.queue.append(len(self._scans) - 1)

    def settle(self) -> None:
        """Draw the rest of a pending re-render at once: for a map to keep (a patrol's end, a
        map save), never for the navigator's once-a-second map."""
        if self.rerendering is not None:
            self._redraw_share(len(self.rerendering.queue))

    def _rerender_step(self) -> None:
        """This scan's share of a pending re-render (none on the scan that solved: the solve
        was its work)."""
        if self.rerendering is not None and self.rerendering.since < self.scans:
            self._redraw_share(BUDGET)

    def _redraw_share(self, budget: int) -> None:
        """``budget`` more kept scans of the pending re-render; once all are drawn, it replaces
        its region of the map at once."""
        r = self.rerendering
        self.rerendered += r.step(self._draw, budget)
        if r.done:
            self.grid.replace(r.shadow)
            self.rerendering = None
            self.swaps += 1
            self._swapped = True

    def _draw(self, grid: LogOddsGrid, i: int) -> None:
        """Kept scan ``i`` at its pose now, into ``grid`` (a re-render's shadow: all of it)."""
        s = self._scans[i]
        pose = self._scan_pose(s)
        sensor = compose(pose, self.mount)
        grid.integrate((sensor.x, sensor.y), transform_points(pose, s.points.astype(np.float64)), grid.whole)
