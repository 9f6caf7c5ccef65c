"""How far the robot's map has drifted from the mission's frame, here: read off the pots.

A mission's pot poses are in the frame the map had when they were written (the survey's map, or
the world's). SLAM's map drifts from that frame slowly and smoothly, a few centimetres over tens
of metres (on a 36 m two-bay greenhouse, 5-10 cm at the far end), so a pot's tag read at arrival
places it off the mission's pose by the drift even when nobody touched it. With ``moved_xy`` at
5 cm, 143 to 164 of 180 unmoved pots there were reported ``moved``.

Drift is shared by neighbours; a moved pot is alone. So the offsets (measured minus mission) of
the pots already located near a pot say what its offset would be had it not moved: when at least
``MIN_NEIGHBOURS`` of them within ``radius``, and more than half of them, agree (lie within half
of ``moved_xy`` of the neighbours' median offset), their mean is the local drift, and the pot has
moved only when its own offset is farther than ``moved_xy`` from it. A few moved pots among the
neighbours are outvoted; where they do not agree, or there are too few (the first two pots of a
patrol), the drift is taken as zero, as before. The robot also approaches each pot at the
mission's pose carried by the drift there, so a pot off by the drift alone is stood at right the
first time (on that greenhouse one stood at 7.6 cm off missed its bloom). The report still gives
a moved pot's position in the mission's frame (``in_mission_frame``: measured less the drift
there), which ``mission update`` writes back, so the next patrol does not find it moved again.
"""
from __future__ import annotations

import numpy as np

from behaviours.visit import PotVisit

MIN_NEIGHBOURS = 2
"""Located pots that must agree before their offset counts as the map's drift."""


class MapDrift:
    def __init__(self, radius: float, agree: float):
        self.radius, self.agree = radius, agree
        self._at: list[tuple[float, float]] = []
        self._offset: list[tuple[float, float]] = []

    def record(self, mission_xy: tuple[float, float], offset: tuple[float, float]) -> None:
        """A located pot's offset, measured minus mission, at its mission position."""
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
        agree = off[np.hypot(*(off - np.median(off, axis=0)).T) <= self.agree]
        if len(agree) < MIN_NEIGHBOURS or 2 * len(agree) <= len(off):
            return 0.0, 0.0
        mean = agree.mean(axis=0)
        return float(mean[0]), float(mean[1])


def in_mission_frame(visit: PotVisit) -> tuple[float, float, float]:
    """Where the located pot stands in the mission's frame: its map position less the map's drift
    there. What the report's ``moved`` says and ``mission update`` writes, so the next patrol,
    whose map drifts alike, finds the pot where the mission now puts it."""
    x, y, facing = visit.located
    return x - visit.drift[0], y - visit.drift[1], facing
