"""Climate sources: readings keyed by tag id (the original's "climate data" per tag record,
reference/upstream.md). A greenhouse data source is a table of readings per tag
(:class:`TableClimate`; the sim's is the world file's ``climate`` section); a robot without one
uses :class:`NoClimate`."""
from __future__ import annotations

from typing import Mapping, Protocol


class ClimateSource(Protocol):
    def reading(self, tag: int) -> dict[str, float] | None:
        """What the source knows for ``tag`` (only the fields it knows), or None."""


class NoClimate:
    def reading(self, tag: int) -> dict[str, float] | None:
        return None


class TableClimate:
    """Readings per tag id; each reading holds only the fields known (no None values)."""

    def __init__(self, table: Mapping[int, Mapping[str, float]]):
        self._table = {int(tag): dict(r) for tag, r in table.items()}

    def reading(self, tag: int) -> dict[str, float] | None:
        found = self._table.get(tag)
        return dict(found) if found else None
