"""How far the robot's map has drifted from the mission's frame, here: read off the pots.

A mission's pot poses are in the frame the map had when they were written (the survey's map, or
the world's). SLAM's map drifts from that frame slowly and smoothly, a few centimetres over tens
of metres (on a 36 m two-bay greenhouse, ~5 cm at the far end), so a pot's tag read at arrival
places it off the mission's pose by the drift even when nobody touched it. With ``moved_xy`` at
5 cm, 143 of 180 unmoved pots there were reported ``moved`` and approached a second time.

Drift is shared by neighbours; a moved pot is alone. So the offsets (measured minus mission) of
the unmoved pots already located near a pot say what its offset would be had it not moved: when
at least ``MIN_NEIGHBOURS`` of them within ``radius`` agree (all within half of ``moved_xy`` of
their mean), that mean is the local drift, and the pot has moved only when its own offset is
farther than ``moved_xy`` from it. Where neighbours disagree (several moved pots about) or there
are too few (the first pots of a patrol), the drift is taken as zero, as before. The report
still gives the measured position in the map frame.
"""
from __future__ import annotations

import numpy as np

MIN_NEIGHBOURS = 2
"""Unmoved pots that must agree before their offset counts as the map's drift."""


class MapDrift:
    def __init__(self, radius: float, agree: float):
        self.radius, self.agree = radius, agree
        self._at: list[tuple[float, float]] = []
        self._offset: list[tuple[float, float]] = []

    def record(self, mission_xy: tuple[float, float], offset: tuple[float, float]) -> None:
        """An unmoved pot's offset, measured minus mission, at its mission position."""
        self._at.append(mission_xy)
        self._offset.append(offset)

    def near(self, x: float, y: float) -> tuple[float, float]:
        """The map's drift at mission position (x, y): (dx, dy), zero when it cannot be told."""
        if len(self._at) < MIN_NEIGHBOURS:
            return 0.0, 0.0
        at, off = np.asarray(self._at), np.asarray(self._offset)
        off = off[np.hypot(at[:, 0] - x, at[:, 1] - y) <= self.radius]
        if len(off) < MIN_NEIGHBOURS:
            return 0.0, 0.0
        mean = off.mean(axis=0)
        if np.hypot(*(off - mean).T).max() > self.agree:
            return 0.0, 0.0
        return float(mean[0]), float(mean[1])
