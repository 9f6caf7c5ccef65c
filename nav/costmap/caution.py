"""The caution layer: a person's berth, where there is room for it, round what the map
explains but cannot tell from someone (issue 28 item 2).

The person tracker takes what the map held when the patrol started, and the long components
of the live map, for the greenhouse (``perception.people.explained``): never tracked, so no
person rule holds for it. Most of that is walls, dividers and benches, which are straight; what
is neither a straight run nor a known pot (``nav.structure.odd_blobs``, handed on by
``mission.runtime.people`` as things standing still) may be a worker who crouched there before
the patrol, or one 5 cm from a divider, one component with it (safety.people seed 1: passed at
0.11 m, the least clearance of the bench), or a crate. With a person's keep-out round such a
thing, a pot beside a crate could not be approached; with the inflation's thin halo alone (the
seed's 0.25 m, which the pots' approach poses need), paths skim them.

So the global costmap prices a person's passing clearance round each without forbidding it: a
cost that falls from ``HIGH`` at the robot's body touching the thing to nothing at the person
layer's ``clearance`` (0.3 m) body to body, never inscribed or lethal. NavFn pays for crossing
it, so a plan keeps the whole berth wherever the aisle is wide enough, takes what there is in a
narrower one, and still ends at a pose beside the thing. Only the global costmap has it: MPPI
follows the plan, and the local costmap's inflation is what it must never cross. Tracks not yet
shown to be people are not given it: a crate on a pot's approach pose merged with the pot
behind it in the scan, and the berth kept the robot from the look beside it
(tests/mission/test_blocked_approach.py).
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
