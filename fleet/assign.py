"""From one mission to one patrol per robot: the dispatcher's first step (spec/fleet.md "The
fleet patrol").

The fleet shares the mission's map frame; each robot knows its dock in it. This measures the
planner's path lengths between the pots' approach poses (``nav.path_lengths``, where the robot
stops, as ``order: shortest`` does) and from each dock, labels each approach pose with its aisle
(``fleet.aisles``, when there is a map), splits the pots (``fleet.split``), and writes each robot
an ordinary mission of its pots in the split's order (``order: as_listed``: the split already
ordered them) ending at its own dock, in that robot's own map frame: a runtime mapping from its
dock has its map origin there (spec/mission.md), so the pots are moved from the fleet's frame
into the dock's. A robot given no pots gets no mission (it stays on its dock).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from fleet.aisles import NO_AISLE, find_aisles
from fleet.split import Split, split_pots
from hw.odometry import wrap_angle
from mission.patrol.mission_file import Home, Mission, MissionPot
from nav.costmap.grid import CostGrid
from nav.occupancy import OccupancyMap
from nav.path_lengths import lengths_from, path_lengths

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class Assignment:
    split: Split
    missions: dict[str, Mission]
    """Each robot's patrol, in its own map frame (robots with no pots: none)."""
    aisles: np.ndarray
    """Each mission pot's aisle (``fleet.aisles.NO_AISLE``: none, or no map)."""


def assign(mission: Mission, grid: CostGrid, docks: Mapping[str, Pose], up: Sequence[str] | None = None,
           occupancy: OccupancyMap | None = None) -> Assignment:
    """Split ``mission``'s pots between the robots ``up`` (default every robot with a dock).
    ``grid``: the costmap the planner measures on; ``docks``: each robot's dock in the
    mission's frame; ``occupancy``: the map the aisles come from."""
    stops = np.array([mission.approach(p)[:2] for p in mission.pots])
    if occupancy is not None:
        pots = np.array([(p.x, p.y, p.facing) for p in mission.pots])
        aisles = find_aisles(occupancy, pots).at(stops[:, 0], stops[:, 1])
    else:
        aisles = np.full(len(stops), NO_AISLE)
    robots = sorted(up if up is not None else docks)
    split = split_pots(path_lengths(grid, stops), {r: lengths_from(grid, docks[r][:2], stops) for r in robots}, aisles)
    missions = {r: _robot_mission(mission, [mission.pots[k] for k in split.parts[r]], docks[r])
                for r in robots if split.parts[r]}
    return Assignment(split, missions, aisles)


def _robot_mission(mission: Mission, pots: list[MissionPot], dock: Pose) -> Mission:
    """The pots (fleet frame) as a mission in the frame of a robot whose map starts at ``dock``."""
    return mission.model_copy(update={"pots": [in_dock_frame(p, dock) for p in pots], "order": "as_listed",
                                      "home": Home(x=0.0, y=0.0, yaw=0.0)})


def in_dock_frame(pot: MissionPot, dock: Pose) -> MissionPot:
    """``pot`` seen from ``dock`` (x forward, y left, the dock's heading zero)."""
    dx, dy = pot.x - dock[0], pot.y - dock[1]
    c, s = math.cos(dock[2]), math.sin(dock[2])
    return pot.model_copy(update={"x": c * dx + s * dy, "y": -s * dx + c * dy, "facing": wrap_angle(pot.facing - dock[2])})
