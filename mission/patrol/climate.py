"""Climate sources: readings keyed by tag id (the original's "climate data" per tag record,
reference/upstream.md). The sim's source reads the world file's ``climate`` section; a robot
without a greenhouse data source uses :class:`NoClimate`."""
from __future__ import annotations

from typing import Protocol

from sim.world import World


class ClimateSource(Protocol):
    def reading(self, tag: int) -> dict[str, float] | None:
        """What the source knows for ``tag`` (only the fields it knows), or None."""


class NoClimate:
    def reading(self, tag: int) -> dict[str, float] | None:
        return None


class WorldClimate:
    def __init__(self, world: World):
        self._table = {tag: c.model_dump(exclude_none=True) for tag, c in world.climate.items()}

    def reading(self, tag: int) -> dict[str, float] | None:
        found = self._table.get(tag)
        return dict(found) if found else None
