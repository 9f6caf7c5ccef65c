"""The order a patrol visits its pots in (spec/mission.md ``order``).

Distances are between *approach poses*, where the robot actually stops, and the tour starts at
the robot's pose when the patrol begins:

- ``as_listed``: the mission file's order;
- ``nearest``: greedy nearest-neighbour in straight lines, ties to the pot listed first;
- ``shortest``: a short tour over the planner's path lengths (``nav.tour``: nearest-neighbour
  improved by 2-opt and Or-opt), ending at home when the patrol returns there, so the last leg
  counts too. Never longer than the nearest-neighbour tour over the same lengths.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from mission.patrol.mission_file import Mission, MissionPot
from nav.tour import nearest_neighbour, shortest_tour

Lengths = Callable[[np.ndarray], np.ndarray]
"""(N, 2) map-frame points -> (N, N) path lengths, m."""


def straight_lines(points: np.ndarray) -> np.ndarray:
    pts = np.asarray(points, dtype=float)
    return np.hypot(*(pts[:, None, :] - pts[None, :, :]).transpose(2, 0, 1))


def visit_order(m: Mission, start_xy: tuple[float, float], lengths: Lengths = straight_lines) -> list[MissionPot]:
    """The pots in the order the patrol visits them; ``lengths`` measures ``shortest`` (the
    planner's path lengths on the robot, straight lines by default)."""
    if m.order == "as_listed":
        return list(m.pots)
    stops = [m.approach(p)[:2] for p in m.pots]
    if m.order == "nearest":
        idx = nearest_neighbour(straight_lines(np.array([start_xy, *stops])), 0, list(range(1, len(stops) + 1)))
    else:
        home = [(m.home.x, m.home.y)] if m.return_home else []
        points = np.array([start_xy, *stops, *home])
        idx = shortest_tour(lengths(points), 0, len(points) - 1 if home else None)
    return [m.pots[k - 1] for k in idx]
