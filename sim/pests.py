"""Where the sim puts a plant's pest: on a bloom or on a leaf (spec/world.md ``bug``).

A world file says only *whether* a plant has a pest. The sim decides where, the same way in
every run of the same file: a plant with no bloom has it on a leaf (spec/world.md); a flowering
plant has it on a leaf for about ``leaf_pest_share`` of pots (``sim.config.GreenhouseGeometry``),
else on its first bloom, because growers' pests (aphids, whitefly, thrips) sit on leaves at
least as often as on flowers (issue 30). The draw is a CRC-32 of the world's name and the pot's
id, not a random generator: no seed to thread through, and a generated world (named after its
seed) gets a different mix from every seed. The leaf is one of the two back leaves, which stand
highest and show over the blooms in the wrist frame (``sim.greenhouse``).

Public API: :class:`PestSite`, :func:`pest_site`, :data:`PEST_LEAVES`.
"""
from __future__ import annotations

import zlib
from dataclasses import dataclass
from typing import Literal

from sim.world import Pot

PEST_LEAVES = (3, 4)
"""Indices of the leaves a pest may sit on (``sim.greenhouse``'s foliage): the two at the back."""


@dataclass(frozen=True)
class PestSite:
    on: Literal["bloom", "leaf"]
    """What the dark spot sits on."""
    index: int
    """Which bloom or leaf (``pot_<id>_bloom_<index>`` / ``pot_<id>_leaf_<index>``)."""


def pest_site(world_name: str, pot: Pot, leaf_share: float) -> PestSite | None:
    """Where ``pot``'s pest is drawn (None: the pot has no pest)."""
    if not pot.bug:
        return None
    draw = zlib.crc32(f"{world_name}/{pot.id}".encode()) / 2**32  # uniform in [0, 1)
    if pot.flower != "none" and draw >= leaf_share:
        return PestSite("bloom", 0)
    leaf = PEST_LEAVES[int(draw * 1e6) % len(PEST_LEAVES)]
    return PestSite("leaf", leaf)


__all__ = ["PestSite", "pest_site", "PEST_LEAVES"]
