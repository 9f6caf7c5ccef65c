"""Loop closure: find a revisit, match the scan to the map made there, and check the match.

A keyframe is a loop candidate when an older keyframe, left at least ``loop_min_travel`` of
driving ago, lies within ``loop_search_radius`` of the current estimate (slam_toolbox's
distance-based search). The current keyframe's scan is registered (kiss-icp's registration)
against a submap of the candidate and its neighbours placed by their graph poses, starting from
the current estimate; the match is accepted only when

* it moved the estimate less than ``loop_max_correction`` (half a pot spacing: sliding onto the
  neighbouring pot is a false match, not a correction), and
* at least ``loop_fitness`` of the scan's points end within ``loop_inlier_distance`` of the
  submap (checked on a dilated raster of the submap, no KD-tree needed), and
* it is unique: no other alignment of the scan, shifted ``UNIQUE_EXCLUDE`` to ``UNIQUE_SEARCH``
  metres in any direction, fits nearly as well (it must fit ``UNIQUE_LEAD`` more of the
  scan's points than the best of them). In the middle of a long row
  of pots every metre, with the end walls out of the lidar's reach, the scan fits the row one
  pot along as well as here: such a match cannot tell which pot it is at, and a closure to the
  wrong pot would bend the map by a metre, so it is refused and the chain is trusted until a
  place with something to tell it by (a cross aisle, a wall, a doorway). This is the classic trap
  of repetitive scenes (Olson's "ambiguity" test in place recognition: the best match must
  stand out from the second best).

The accepted result is the relative pose between the two keyframes: a pose-graph edge.
"""
from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from kiss_icp.mapping import VoxelHashMap
from kiss_icp.registration import get_registration

from hw.odometry import Pose2D
from nav.frames import compose, distance, from_matrix, inverse, to_matrix, transform_points
from nav.slam.config import SlamConfig
from nav.slam.lidar_odometry import kiss_config

#: Keyframes either side of the candidate that make up its submap.
SUBMAP_HALF_WIDTH = 6
#: Correspondence gate of the loop match, m: wider than the front end's (the drift being
#: corrected may be a few centimetres to decimetres), narrower than half a pot spacing.
MATCH_GATE = 0.25
#: Rival alignments are looked for this far round the match in x and y, m: past a pot pitch.
UNIQUE_SEARCH = 1.2
#: ... on a grid this fine, m (a fifth of the inlier raster's dilated reach either way).
UNIQUE_STEP = 0.1
#: Shifts nearer the match than this are the match itself, m.
UNIQUE_EXCLUDE = 0.3
#: The match must fit this much more of the scan's points than any rival, or it is ambiguous:
#: mid-row the rival one pot along fits exactly as many; from 4 m off an end wall, the wall's
#: returns (a narrow slice of the scan down the aisle) put the rival 9 % behind.
UNIQUE_LEAD = 0.05


@dataclass(frozen=True)
class LoopMatch:
    candidate: int
    relative: Pose2D
    """The current keyframe as seen from the candidate keyframe."""
    correction: float
    """How far the match moved the current estimate, m."""
    fitness: float


class LoopCloser:
    def __init__(self, cfg: SlamConfig):
        self.cfg = cfg
        self.registration = get_registration(kiss_config(cfg))

    def candidate(self, poses: np.ndarray, travel: np.ndarray, k: int) -> int | None:
        """The nearest old-enough keyframe to keyframe ``k`` within the search radius, or None."""
        old = np.flatnonzero(travel[k] - travel[:k] >= self.cfg.loop_min_travel)
        if len(old) == 0:
            return None
        d = np.hypot(poses[old, 0] - poses[k, 0], poses[old, 1] - poses[k, 1])
        best = int(np.argmin(d))
        return int(old[best]) if d[best] <= self.cfg.loop_search_radius else None

    def match(self, poses: np.ndarray, scans: list[np.ndarray], candidate: int, k: int) -> LoopMatch | None:
        """Register keyframe ``k``'s scan (``scans``: each keyframe's (N, 3) ``base_link``
        points) against the candidate's submap; None if not accepted."""
        cfg = self.cfg
        lo, hi = max(0, candidate - SUBMAP_HALF_WIDTH), min(k, candidate + SUBMAP_HALF_WIDTH + 1)
        submap = np.vstack([transform_points(_pose(poses[i]), scans[i][:, :2]) for i in range(lo, hi)])
        voxels = VoxelHashMap(cfg.voxel_size, 1e6, cfg.max_points_per_voxel)
        voxels.add_points(np.column_stack([submap, np.zeros(len(submap))]))
        guess = _pose(poses[k])
        source = np.asarray(scans[k], dtype=np.float64)
        result = from_matrix(self.registration.align_points_to_map(source, voxels, to_matrix(guess),
                                                                   MATCH_GATE, MATCH_GATE / 3))
        correction = distance(result, guess)
        if correction > cfg.loop_max_correction:
            return None
        placed = transform_points(result, source[:, :2])
        fitness, rival = _fitness(submap, placed, cfg.loop_inlier_distance, _rival_shifts())
        if fitness < cfg.loop_fitness or fitness - rival < UNIQUE_LEAD:
            return None
        return LoopMatch(candidate, compose(inverse(_pose(poses[candidate])), result), correction, fitness)


def _pose(row: np.ndarray) -> Pose2D:
    return Pose2D(float(row[0]), float(row[1]), float(row[2]))


def _rival_shifts() -> np.ndarray:
    """(M, 2) translations tried for a rival alignment: a grid out to ``UNIQUE_SEARCH``, the
    match's own neighbourhood left out."""
    k = np.arange(-UNIQUE_SEARCH, UNIQUE_SEARCH + 1e-9, UNIQUE_STEP)
    grid = np.stack(np.meshgrid(k, k), axis=-1).reshape(-1, 2)
    return grid[np.hypot(grid[:, 0], grid[:, 1]) >= UNIQUE_EXCLUDE]


def _fitness(reference: np.ndarray, points: np.ndarray, inlier: float, shifts: np.ndarray) -> tuple[float, float]:
    """Share of ``points`` within ~``inlier`` of some ``reference`` point (raster at ``inlier``,
    dilated by one cell), and the best share among the points moved by each of ``shifts``."""
    if not len(points):
        return 0.0, 0.0
    reach = float(np.abs(shifts).max()) if len(shifts) else 0.0
    lo = np.minimum(reference.min(axis=0), points.min(axis=0)) - 2 * inlier - reach
    hi = np.maximum(reference.max(axis=0), points.max(axis=0)) + 2 * inlier + reach
    shape = (int((hi[1] - lo[1]) / inlier) + 2, int((hi[0] - lo[0]) / inlier) + 2)
    ref = np.floor((reference - lo) / inlier).astype(np.int64)
    raster = np.zeros(shape, dtype=np.uint8)
    raster[ref[:, 1], ref[:, 0]] = 1
    raster = cv2.dilate(raster, np.ones((3, 3), np.uint8))
    cells = np.floor((points[None, :, :] + np.vstack([[0.0, 0.0], shifts])[:, None, :] - lo) / inlier).astype(np.int64)
    share = raster[cells[..., 1], cells[..., 0]].mean(axis=1)
    return float(share[0]), float(share[1:].max(initial=0.0))
