"""What the greenhouse itself accounts for, to the person tracker: the first map, the structure
SLAM finds since, the known pots.

The person tracker needs to know what the greenhouse itself explains, so that a pot is not a
person: the map as it stood when the patrol started plus the pots the mission lists
(``perception.people.explained.StaticScene``: not the live SLAM map as it is, which writes in a
worker who stands still). So it is built once the patrol says which pots it knows
(``People.watch``), and frozen at the map of the first tick that has one (SLAM's first map from
the dock, or the saved one AMCL localises on). A patrol mapping from the dock has seen little of
its walls then, and every wall it meets later, broken into short arcs by the pots in front and grazing angles,
would be a person: the default patrol took 244 s of robot time instead of 123, slowed and held
by walls. So the scene also takes in, each time SLAM hands a new map, its *structure*: the
occupied components longer than any person (``max_extent``, the tracker's own bound, bounding-box
diagonal, after closing 0.1 m gaps), which are walls and benches; a worker standing still, a
crouching one or a crate stays a small blob and is never taken in. Whatever is tracked is cut
out of the map the structure is read from first (``without``, the spots ``see`` is handed), so a
grower paused against a wall is not taken in with it; and where someone was found standing since
the first map, that map stops explaining (``clear``, ``mission.runtime.stood_at_start``).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Optional, Sequence

import cv2
import numpy as np

from mission.runtime.stood_at_start import clear_round
from nav.grid_geometry import GridGeometry, paste
from nav.occupancy import FREE, FREE_MAX, OCCUPIED_MIN, UNKNOWN, OccupancyMap
from nav.structure import long_components
from perception.people.config import PeopleConfig
from perception.people.explained import StaticScene


class Greenhouse:
    """The tracker's scene, grown with every new map: ``scene`` explains what the greenhouse
    holds, ``bare`` the same without the first map (its structure and known pots alone)."""

    def __init__(self, config: PeopleConfig, pots_xy: Sequence[tuple[float, float]], pot_radius: float):
        self.config = config
        self.pots = np.asarray(pots_xy, dtype=float).reshape(-1, 2)
        """(N, 2) the known pots, map frame."""
        self.pot_radius = pot_radius
        self.scene: StaticScene | None = None
        """What the greenhouse explains (None until a map)."""
        self.bare: StaticScene | None = None
        """The scene without the first map: the structure and the known pots."""
        self._first: OccupancyMap | None = None
        self._left: np.ndarray | None = None
        """The first map's occupied cells that no longer explain (on its grid): seen free since
        (someone who stood there left), or someone found standing there."""
        self._live: OccupancyMap | None = None
        self._floor: np.ndarray | None = None
        """The live map's cells any map so far saw free: floor, which a person may stand on."""
        self._long: np.ndarray | None = None
        """The live map's structure, on its grid (``nav.structure``)."""

    def see(self, live: Optional[OccupancyMap],
            tracked: Callable[[], list[tuple[float, float, float]]]) -> None:
        """Take in ``live`` if it is a new map (the first one becomes the first map); ``tracked``
        gives what is tracked now (x, y, radius; map frame), cut from where the structure is read."""
        if live is self._live or live is None:
            return
        if self._first is None:
            self._first, self._left = live, np.zeros(live.occupancy.shape, bool)
        self._floor = floor_seen(live, self._floor, None if self._live is None else self._live.geometry)
        self._live = live
        self._left |= self._first.occupied() & seen_free(live, self._first.geometry, self.config.margin)
        cut = without(live, tracked(), self.config.margin, self._floor)
        self._long = long_components(cut, self.config.max_extent)
        self._freeze()

    def clear(self, spots: list[tuple[float, float]]) -> None:
        """The first map stops explaining round each spot (map frame) someone stands on."""
        clear_round(self._left, self._first.geometry, spots)
        self._freeze()

    def _freeze(self) -> None:
        live, c = self._live, self.config
        self.scene = StaticScene(Cells(live.geometry, self._long | kept(self._first, live, self._left)),
                                 self.pots, self.pot_radius, c.margin)
        self.bare = StaticScene(Cells(live.geometry, self._long), self.pots, self.pot_radius, c.margin)


class Cells:
    """An occupied mask where ``StaticScene`` wants a map (its ``occupied()`` and ``geometry``)."""

    def __init__(self, geometry: GridGeometry, mask: np.ndarray):
        self.geometry, self._mask = geometry, mask

    def occupied(self) -> np.ndarray:
        return self._mask


def kept(first: OccupancyMap, live: OccupancyMap, left: np.ndarray | None = None) -> np.ndarray:
    """On ``live``'s grid: the first map's occupied cells but those ``left`` (on the first map's
    grid: seen free since, or someone found standing there, ``mission.runtime.stood_at_start``)."""
    cells = first.occupied() if left is None else first.occupied() & ~left
    return paste(cells, first.geometry, live.geometry, False)


def floor_seen(live: OccupancyMap, before: np.ndarray | None, on: GridGeometry | None) -> np.ndarray:
    """On ``live``'s grid: the cells ``live`` sees free, and those ``before`` (on the grid ``on``)
    saw free: where a person can stand, which a wall never was."""
    seen = (live.occupancy >= FREE) & (live.occupancy <= FREE_MAX)
    return seen if before is None else seen | paste(before, on, live.geometry, False)


def without(live: OccupancyMap, people: Sequence[tuple[float, float, float]], margin: float,
            floor: np.ndarray | None = None) -> OccupancyMap:
    """``live`` with the cells within radius + ``margin`` of each track (x, y, radius; map frame)
    made unknown, of those seen free before (``floor``, on ``live``'s grid; all when None): what
    the structure is read from. SLAM writes in a person who stands still, and a
    worker standing within a gap's closing (0.1 m) of a wall, a bench or their own cart pushed
    against one became part of that long component, so explained, so no longer a person: the
    robot drove past a grower paused at the end of a cross aisle at 0.15 m (safety.people seed 3,
    773-779 s), whose cart then turned back through it. Whatever is being tracked is never taken
    for the greenhouse; once they are gone, their cells join whatever they touch again. Only
    floor is cut: a false track on a wall (its seen centre shifting as the robot drives by) would
    otherwise keep that wall from ever being explained, and so itself alive, for good."""
    if not people:
        return live
    mask = np.zeros(live.occupancy.shape, np.uint8)
    res = live.resolution
    for x, y, r in people:
        ix, iy = live.geometry.cell_of(x, y)
        cv2.circle(mask, (int(ix), int(iy)), int(np.ceil((r + margin) / res)), 1, -1)
    cut = live.occupancy.copy()
    cut[mask.astype(bool) & (True if floor is None else floor)] = UNKNOWN
    return replace(live, occupancy=cut)


def seen_free(live: OccupancyMap, on: GridGeometry, margin: float) -> np.ndarray:
    """On the grid ``on``: the cells ``live`` knows to be free with nothing occupied within
    ``margin``. A worker standing in the first map (at the dock, on their round) is not the
    greenhouse: once they walk off, the cells they stood on are seen free, and the first map
    stops explaining them (people-crossing-no-yield: a grower whose round starts beside the first
    pot was explained away each time they came back to stand there). The margin keeps a crate or
    a pot's rim, drawn a cell off in the first map, from wearing away at its edges."""
    v = paste(live.occupancy, live.geometry, on, np.int8(UNKNOWN))
    cells = int(np.ceil(margin / on.resolution))
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * cells + 1, 2 * cells + 1))
    near = cv2.dilate((v >= OCCUPIED_MIN).astype(np.uint8), k).astype(bool)
    return (v >= FREE) & (v <= FREE_MAX) & ~near
