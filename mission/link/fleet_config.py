"""Fleet settings: what the dispatcher of a fleet patrol needs beyond the mission (spec/fleet.md).

Beside ``link`` in the one config (``fleet.*``, ``LUPIN_FLEET__HANDOVER_AFTER``): the dispatcher
(``fleet.dispatcher``) reads it; a robot's runtime carries it unused.
"""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


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
    at the K-th."""
