"""What a respawned SLAM worker needs to go on mapping where the lost one stood (issue 29, item 4).

A worker that truly wedges (or crashes) is killed and replaced; before this, the replacement
started an empty map, and mid-patrol the robot lost its map. The mapper's state that a restart
needs is small and grows only by appending:

* the pose graph: keyframe poses (replaced whole only after a solve), its edges, each keyframe's
  points (what loop closure matches against) and the travel along the chain;
* the kept scans (one every 0.2 m, float16: what a re-render after a loop closure draws from);
* the map: the worker already hands it back once a second, and once more when a solve's
  re-render is swapped in (the map must follow the graph it is kept with); while a re-render is
  being drawn (``nav.slam.rerender``), its region, so a replacement draws it again from the
  kept scans rather than keep that region at the poses the solve moved away from.

The worker sends what is new with each reply (a ``Delta``: a scan's worth, a few KB when a
keyframe or a kept scan was added and nothing otherwise), and the supervisor folds it into a
``Checkpoint`` held in the runtime process. The parent is the simplest robust place: it
outlives any worker, however the worker dies (a busy loop, a blocked call, a crash, the OOM
killer); it needs no file format, no disk write on the runtime's thread and no clean-up; the
per-scan cost is a few list appends. (Keeping it across a restart of the runtime itself would be
one more step: writing this object to the runtime's state directory; not needed for a worker.)

The operator's map reset is the exception: it drops the checkpoint, so the fresh worker starts an
empty map (seed, "Resetting the map").
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from hw.odometry import Pose2D
from nav.occupancy import OccupancyMap
from nav.slam.pose_graph import Edge


@dataclass(frozen=True)
class KeptScan:
    index: int
    """Which scan of the run it was (0, 1, ...)."""
    keyframe: int
    relative: Pose2D
    """The scan's pose as seen from its keyframe."""
    points: np.ndarray
    """float16 (N, 2) returns in ``base_link`` (4 mm at 8 m: a tenth of a map cell)."""
    reach: float
    """The farthest return from the robot, m: the scan touches no cell farther away."""


@dataclass(frozen=True)
class Delta:
    """What one scan added to the mapper's state (all empty for most scans)."""

    first_node: int
    """Keyframe poses from this node on are replaced by ``poses`` (0 after a solve)."""
    poses: np.ndarray
    """(M, 3) keyframe poses (x, y, yaw) in ``map`` from ``first_node`` on."""
    edges: tuple[Edge, ...] = ()
    keyframe_points: tuple[np.ndarray, ...] = ()
    travel: tuple[float, ...] = ()
    """Travel along the chain to each new keyframe, m."""
    scans: tuple[KeptScan, ...] = ()
    counters: tuple[int, int, int, float] = (0, 0, 0, 0.0)
    """Scans processed, loop closures, solves, and the travel before the next loop is sought."""
    occupancy: Optional[OccupancyMap] = None
    """The map when a solve's re-render was swapped in (else None: the once-a-second map stands)."""
    rerender: Optional[tuple[float, float, float, float]] = None
    """The region (x0, y0, x1, y1, m) a re-render is drawing after this scan (None: none)."""

    @property
    def nbytes(self) -> int:
        """Array bytes carried: what the checkpoint costs the pipe for this scan."""
        return int(self.poses.nbytes + sum(p.nbytes for p in self.keyframe_points)
                   + sum(s.points.nbytes for s in self.scans)
                   + (self.occupancy.occupancy.nbytes if self.occupancy is not None else 0))


@dataclass
class Checkpoint:
    """The sum of every delta so far, plus the latest map: a restart starts from this."""

    poses: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    edges: list[Edge] = field(default_factory=list)
    keyframe_points: list[np.ndarray] = field(default_factory=list)
    travel: list[float] = field(default_factory=list)
    scans: list[KeptScan] = field(default_factory=list)
    counters: tuple[int, int, int, float] = (0, 0, 0, 0.0)
    occupancy: Optional[OccupancyMap] = None
    rerender: Optional[tuple[float, float, float, float]] = None
    """The region a re-render was drawing: the map there is at the poses before the solve."""

    @property
    def solves(self) -> int:
        """Pose-graph solves so far: each moves the robot back onto the map it made before
        (``mission.patrol.map_drift`` starts reading the drift afresh after one)."""
        return int(self.counters[2])

    @property
    def empty(self) -> bool:
        """Nothing to start from (no keyframe yet, or no map yet)."""
        return len(self.poses) == 0 or self.occupancy is None

    def apply(self, delta: Delta) -> None:
        """Fold one scan's delta in: appends, and the poses from ``first_node`` on."""
        self.poses = np.vstack([self.poses[:delta.first_node], delta.poses]) if len(delta.poses) else self.poses
        self.edges += delta.edges
        self.keyframe_points += delta.keyframe_points
        self.travel += delta.travel
        self.scans += delta.scans
        self.counters = delta.counters
        self.rerender = delta.rerender
        if delta.occupancy is not None:
            self.occupancy = delta.occupancy

    def map(self, occupancy: OccupancyMap) -> None:
        """The map the worker handed back (once a second)."""
        self.occupancy = occupancy

    @property
    def nbytes(self) -> int:
        return int(self.poses.nbytes + sum(p.nbytes for p in self.keyframe_points)
                   + sum(s.points.nbytes for s in self.scans)
                   + (self.occupancy.occupancy.nbytes if self.occupancy is not None else 0))
