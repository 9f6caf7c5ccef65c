"""Nav2's likelihood-field sensor model, precomputed once per map.

A beam is scored by where its endpoint lands, not by tracing it (Thrun et al., Probabilistic
Robotics, 6.4): with ``d`` the distance from the endpoint to the nearest occupied cell,

    pz = z_hit exp(-d^2 / (2 sigma_hit^2)) + z_rand / max_range

and, as Nav2's ``LikelihoodFieldModel``, a particle's weight is ``1 + sum(pz^3)`` over its
beams: an ad hoc sum of cubes in place of the product, which keeps a few unexpected returns
(a plant, a person) from zeroing an otherwise right particle. ``score`` returns its log, so
weights can be multiplied across updates (resample_interval > 1) without overflow.

``d`` is the exact Euclidean distance transform of the occupied cells (OpenCV, in one pass;
Nav2's ``map_update_cspace`` does the same by brushfire), clipped at
``laser_likelihood_max_dist``. An endpoint off the map scores as that maximum distance, as in
Nav2. Unknown cells inside the map keep their distance to the nearest obstacle, as in Nav2,
rather than counting as maximally far (Thrun's choice): a saved SLAM map has unknown cells
just behind every wall, and range noise puts a share of the true pose's endpoints there.
Because ``pz^3`` depends on the cell alone it is tabulated per cell, and a lookup is one
gather per endpoint, vectorised over particles x beams.
"""
from __future__ import annotations

import cv2
import numpy as np

from nav.occupancy import OccupancyMap


class LikelihoodField:
    def __init__(self, occupancy: OccupancyMap, max_dist: float, z_hit: float, z_rand: float, sigma_hit: float,
                 max_range: float):
        self.map = occupancy
        self.max_dist = float(max_dist)
        not_occupied = (~occupancy.occupied()).astype(np.uint8)  # zeros where the obstacles are
        if not_occupied.all():
            dist = np.full(not_occupied.shape, self.max_dist, np.float64)
        else:
            dist = cv2.distanceTransform(not_occupied, cv2.DIST_L2, cv2.DIST_MASK_PRECISE).astype(np.float64)
            dist = np.minimum(dist * occupancy.resolution, self.max_dist)
        self.distance = dist
        """[iy, ix] distance from each cell's centre to the nearest occupied cell's, m, clipped."""

        def cube(d):
            return (z_hit * np.exp(-(d * d) / (2.0 * sigma_hit * sigma_hit)) + z_rand / max_range) ** 3

        self._cubes = np.append(cube(dist).ravel(), cube(self.max_dist))  # last entry: off the map
        self._w, self._h = occupancy.width, occupancy.height

    def _index(self, points_xy: np.ndarray) -> np.ndarray:
        """Flat cell index of each point, or the off-map slot."""
        idx = self.map.geometry.flat_index(points_xy[..., 0], points_xy[..., 1])
        return np.where(idx >= 0, idx, self._w * self._h)

    def distance_at(self, points_xy: np.ndarray) -> np.ndarray:
        """Distance to the nearest obstacle at each point (..., 2), m (the maximum off the map)."""
        return np.append(self.distance.ravel(), self.max_dist)[self._index(np.asarray(points_xy, np.float64))]

    def score(self, points_xy: np.ndarray) -> np.ndarray:
        """(P,) log of Nav2's weight ``1 + sum(pz^3)`` for beam endpoints ``points_xy`` (P, B, 2),
        given in the map frame."""
        return np.log1p(self._cubes[self._index(points_xy)].sum(axis=-1))
