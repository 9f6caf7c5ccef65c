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
neighbours are outvoted.

A read's offset is the robot's localisation error when it read the tag, and that changes along
the patrol, not only along the greenhouse: smoothly while SLAM tracks its scans, by a jump when
a loop closure's solve pulls the robot back onto the map it made before. So the neighbours
asked are the few (``RECENT``) located nearest in time to the pot's own read since SLAM last
solved its pose graph (``corrections``). On the 180-pot patrol in listed order the last row's
pots were read at -0.20 to -0.24 m, the row beside them 150 s earlier at -0.15 to -0.17 m, and
those older neighbours, outvoting the recent ones, made four unmoved pots moved; on the 30 m
two-bay patrol a solve moved the robot 6 cm between two pots of one aisle, and four pots read
in the minute before it were moved: the reads around them were older, from before the error
grew. When those neighbours cannot tell (the first pots of a patrol or after a solve, or the
first past a bay's divider) the pot is judged on every located neighbour near it (zero drift
when they do not agree either) and its moved verdict is provisional: at the patrol's end it is
judged again on the neighbours read nearest in time to it since the same solve, those read
after it included (``PotFinder.rejudge``). Neighbours beyond a wall of the map do not count
(``walls_apart``): the two bays' scans of one divider disagree, so one bay's drift says nothing
of the other's. The robot also approaches each pot at the mission's pose carried by the drift
there, so a pot off by the drift alone is stood at right the first time (on that greenhouse one
stood at 7.6 cm off missed its bloom). The report still gives
a moved pot's position in the mission's frame (``in_mission_frame``: measured less the drift
there), which ``mission update`` writes back, so the next patrol does not find it moved again.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from behaviours.visit import PotVisit
from nav.occupancy import OccupancyMap
from nav.structure import long_components

MIN_NEIGHBOURS = 2
"""Located pots that must agree before their offset counts as the map's drift."""

RECENT = (3, 5)
"""How many located neighbours nearest in time a read's drift is taken from: the three read
nearest it, or, when they do not agree, the five (three outvote one moved pot among them, five
two). Few, because the error changes along the patrol: a centimetre a pot along the 180-pot
greenhouse's last row, so five pots already span four."""

WALL_EXTENT = 1.5
"""A component of the map longer than this (bounding box diagonal, m) is a wall between pots;
pots (0.2 m), their foliage and a row's neighbours in the lidar's shadow are not."""

Apart = Callable[[tuple[float, float], tuple[float, float]], bool]
"""Whether a wall of the map stands between two mission positions."""


def same_side(_a, _b) -> bool:
    """No map (a test, or before SLAM's first map): every neighbour counts."""
    return False


def corrections(localisation) -> int:
    """SLAM's pose-graph solves so far (``nav.slam.checkpoint.Checkpoint.solves``): each moves
    the robot back onto the map it made before. A loop closure that agrees with the graph is not
    solved and moves nothing (on the 180-pot patrol 14 of 142 were solved). 0 for a localisation
    without them (AMCL on a saved map, odometry alone)."""
    return getattr(getattr(localisation, "checkpoint", None), "solves", 0)


def walls_apart(occupancy: OccupancyMap | None, step: float = 0.05) -> Apart:
    """``Apart`` on ``occupancy``: a cell of the map's structure (``nav.structure``: walls,
    dividers, benches longer than ``WALL_EXTENT``) on the straight line between the two
    positions. Across a bay's divider the two bays' scans of the same wall disagree, so the map's
    drift on one side is no guide to the other's (on the 180-pot greenhouse the first pots past
    the divider were reported moved by the other bay's drift)."""
    if occupancy is None:
        return same_side
    walls = long_components(occupancy, WALL_EXTENT)
    g = occupancy.geometry

    def apart(a, b) -> bool:
        n = max(2, int(np.hypot(b[0] - a[0], b[1] - a[1]) / step) + 1)
        ix, iy = g.cell_of(np.linspace(a[0], b[0], n), np.linspace(a[1], b[1], n))
        inside = g.contains(ix, iy)
        return bool(walls[iy[inside], ix[inside]].any())

    return apart


@dataclass(frozen=True)
class Read:
    """A located pot's offset (measured minus mission, m) and when it was read: SLAM's loop
    closures by then and its place in the order of reads."""
    offset: tuple[float, float]
    epoch: int
    seq: int


@dataclass(frozen=True)
class Drift:
    offset: tuple[float, float]
    """The map's drift at the pot, m."""
    known: bool
    """Told by the neighbours read nearest in time since SLAM's last solve (else by every
    neighbour: a provisional verdict)."""


class MapDrift:
    def __init__(self, radius: float, agree: float):
        self.radius, self.agree = radius, agree
        self._reads: dict[tuple[float, float], Read] = {}
        """By mission position: a pot read again counts once, as read last."""
        self.apart: Apart = same_side
        """Which neighbours stand beyond a wall (``walls_apart`` on the map as it is)."""
        self.epoch: Callable[[], int] = lambda: 0
        """SLAM's pose-graph solves so far (``corrections``)."""

    def record(self, mission_xy: tuple[float, float], offset: tuple[float, float]) -> None:
        """A located pot's offset, measured minus mission, at its mission position, read now."""
        self._reads[mission_xy] = Read(offset, self.epoch(), self._next_seq())

    def near(self, x: float, y: float) -> tuple[float, float]:
        """The map's drift at mission position (x, y): (dx, dy), zero when it cannot be told."""
        drift = self.consensus(x, y)
        return drift.offset if drift is not None else (0.0, 0.0)

    def consensus(self, x: float, y: float, again: bool = False) -> Drift | None:
        """The drift of a read at mission position (x, y) now, or with ``again`` of the read
        recorded there (itself left out): from the ``RECENT`` located pots within ``radius`` on
        this side of any wall read nearest in time to it since the same solve (three,
        else five), when ``MIN_NEIGHBOURS`` and most of them agree (known); else from all of them
        (not known); None when they cannot tell either."""
        me = self._reads.get((x, y)) if again else None
        epoch, seq = (me.epoch, me.seq) if me is not None else (self.epoch(), self._next_seq())
        near = [r for at, r in self._reads.items() if at != (x, y) and np.hypot(at[0] - x, at[1] - y) <= self.radius
                and not self.apart((x, y), at)]
        recent = sorted((r for r in near if r.epoch == epoch), key=lambda r: abs(r.seq - seq))
        for reads, known in [*((recent[:k], True) for k in RECENT), (near, False)]:
            mean = self._agreed(np.array([r.offset for r in reads]).reshape(-1, 2))
            if mean is not None:
                return Drift(mean, known)
        return None

    def _next_seq(self) -> int:
        return max((r.seq for r in self._reads.values()), default=-1) + 1

    def _agreed(self, off: np.ndarray) -> tuple[float, float] | None:
        """The mean of the offsets within ``agree`` of their median, when at least
        ``MIN_NEIGHBOURS`` and more than half of them are."""
        if len(off) < MIN_NEIGHBOURS:
            return None
        agree = off[np.hypot(*(off - np.median(off, axis=0)).T) <= self.agree]
        if len(agree) < MIN_NEIGHBOURS or 2 * len(agree) <= len(off):
            return None
        mean = agree.mean(axis=0)
        return float(mean[0]), float(mean[1])


def in_mission_frame(visit: PotVisit) -> tuple[float, float, float]:
    """Where the located pot stands in the mission's frame: its map position less the map's drift
    there. What the report's ``moved`` says and ``mission update`` writes, so the next patrol,
    whose map drifts alike, finds the pot where the mission now puts it."""
    x, y, facing = visit.located
    return x - visit.drift[0], y - visit.drift[1], facing
