"""Fleet settings: what the dispatcher of a fleet patrol needs beyond the mission (spec/fleet.md).

Beside ``link`` in the one config (``fleet.*``, ``LUPIN_FLEET__HANDOVER_AFTER``): the dispatcher
(``fleet.dispatcher``) reads it; a robot's runtime reads its own dock from it, to tell the
others where it is and place them (``mission.link.peers``).
"""
from __future__ import annotations

from typing import Sequence

from pydantic import BaseModel, ConfigDict, Field

from hw.odometry import Pose2D
from nav.frames import compose, inverse


class FleetConfig(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    handover_after: float = Field(60.0, gt=0)
    """A robot's e-stop held longer than this, s of its own clock, and its unfinished pots go to
    the others (spec/fleet.md). A minute: an operator's stop to look at a plant or clear a crate
    is shorter, and a minute of a stopped robot is ~6 pots (seed: ~6 pots a minute) that the
    others can start on; a fleet e-stop hands nothing over (nobody is left to take them)."""
    docks: dict[str, tuple[float, float, float]] = {}
    """Each robot's dock on a farm, x, y (m), yaw (rad) in the fleet's map frame (the mission's:
    the first dock's, so that one is 0, 0, 0). Empty: the sim world's ``spawns``, robot ``rK``
    at the K-th (``spawn_docks``; ``lupin fleet sim`` hands each robot these)."""


def spawn_docks(spawns: Sequence) -> dict[str, tuple[float, float, float]]:
    """The sim world's spawn poses (world frame, each with x, y, yaw) as the docks of r1, r2, ...
    in the first one's frame: the fleet's."""
    to_fleet = inverse(Pose2D(spawns[0].x, spawns[0].y, spawns[0].yaw))
    docks = {}
    for k, s in enumerate(spawns):
        d = compose(to_fleet, Pose2D(s.x, s.y, s.yaw))
        docks[f"r{k + 1}"] = (d.x, d.y, d.yaw)
    return docks
