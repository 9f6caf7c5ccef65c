"""Does a saved map cover a mission? Checked before a patrol localises on it (``--map``).

A patrol on a saved map plans only where the map says the floor is free (AMCL's map is the
global costmap's static layer, and the robot no longer maps as it goes), so every pot's
approach pose must stand on ground the map has seen free: outside the map, on unexplored
(unknown) ground or inside something, the pot would end ``unreachable`` an hour into the patrol.
Better to say so before the robot moves, naming the pot.
"""
from __future__ import annotations

from mission.patrol.mission_file import Mission
from nav.occupancy import FREE_MAX, OccupancyMap


def uncovered_pots(mission: Mission, occupancy: OccupancyMap) -> list[str]:
    """One line per pot whose approach pose the map does not hold as free ground."""
    geo = occupancy.geometry
    out = []
    for pot in mission.pots:
        x, y, _ = mission.approach(pot)
        ix, iy = (int(v) for v in geo.cell_of(x, y))
        if not geo.contains(ix, iy):
            why = "lies outside the map"
        else:
            value = int(occupancy.occupancy[iy, ix])
            why = ("is on ground the map never saw" if value < 0 else
                   "is inside an obstacle on the map" if value > FREE_MAX else "")
        if why:
            out.append(f"pot {pot.id}: its approach pose ({x:.2f}, {y:.2f}) {why}")
    return out
