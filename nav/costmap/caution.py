"""The caution layer: a person's berth, where there is room for it, round what the greenhouse
does not explain (issue 28 item 2).

The person tracker's tracks not shown to be people (``mission.runtime.people``: they have
neither walked nor shown legs) are things neither the map the patrol started with nor the
mission's pots explain: a crate put down since, a moved pot, a worker who has yet to move. To the
lidar a crouching worker is one low block, the same as a crate, and the person rules cannot
hold for a track that may be a crate: with a person's keep-out round every such track, the
box-in-aisle and moved-pot scenarios lost their pots (the approach poses stand within it). With
the inflation's thin halo alone (the seed's 0.25 m, which the pots' approach poses need), paths
skim them.

The issue's rule for these is "treated as a person until shown otherwise", so the global
costmap prices a person's passing clearance round each without forbidding it: a cost that falls
from ``HIGH`` at the robot's body touching the thing to nothing at the person layer's
``clearance`` (0.3 m) body to body, never inscribed or lethal. NavFn pays ``FACTOR`` a unit to
cross it, so a plan keeps the whole berth wherever the aisle is wide enough, takes what there is
in a narrower one, and still ends at a pose beside the thing. Only the global costmap has it:
MPPI follows the plan, and the local costmap's inflation is what it must never cross. What the
first map held is explained, not tracked, and gets no berth (safety.people seed 1: a worker
crouching 5 cm from a divider since before the patrol, passed at 0.11 m).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from nav.costmap.grid import INSCRIBED
from nav.costmap.people import PersonLayer
from nav.grid_geometry import GridGeometry

HIGH = INSCRIBED - 53
"""The cost where the robot's body would touch the thing (200): NavFn's crossing cost there is
4.2 times a free cell's, and well below the inscribed cost, so the berth is never a wall."""


class CautionLayer(PersonLayer):
    """``PersonLayer``'s frame and windows with a soft, still profile: things, not walkers."""

    def apply(self, master: np.ndarray, geometry: GridGeometry) -> np.ndarray:
        things = self.present()
        if not things:
            return master
        out = master.copy()
        for p in things:  # a thing does not walk: its tracked velocity is the view's jitter
            self._stamp(out, geometry, replace(p, vx=0.0, vy=0.0))
        return out

    def _profile(self, d: np.ndarray, keep_out: float) -> np.ndarray:
        clearance = self.config.clearance
        gap = d - (keep_out - clearance)  # body to body
        share = np.clip(1.0 - gap / clearance, 0.0, 1.0) if clearance > 0 else np.zeros_like(gap)
        return (HIGH * share).astype(np.uint8)
