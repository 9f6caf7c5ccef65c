"""A pot whose approach pose is taken is inspected from beside it.

Something that is not the pot can stand on a pot's approach pose: a robot of the fleet that
died there (``fleet.handover_small``: r2 read P20's tag and died on its approach pose; the robot
P20 was handed to was told "goal blocked beyond tolerance" on every try and the pot failed), a
cart parked in the aisle. The pot is still there to be seen: its plate faces the aisle, the
front camera reads a tag far off square, and the wrist's IK look (``mission.patrol.inspect_view``)
frames the plant from off the ideal pose. So when the drive fails and the goal's cell is taken in
the global costmap (inscribed or lethal: the planner says "goal blocked beyond tolerance", or
plans to the nearest free cell and makes no progress there), the robot looks at the pot from
beside what stands there: from
the plate's side, ``SLANTS`` off square on either hand, at the approach distance and ``FARTHER``
out (square on too, there), wherever the robot's body fits in the global costmap (a fleet's dead
robot is drawn in it at its last told pose, ``nav.costmap.robots``), nearest the robot first. The
first look from which the front camera reads the pot's own tag is where the pot is inspected.
Only the plate's side: from behind, the plate cannot be read. A pot with no such look, or none
that reads its tag, still fails, saying so.
"""
from __future__ import annotations

import math

from hw.odometry import Pose2D
from nav.costmap.grid import CostGrid
from nav.frames import compose, inverse
from nav.viewpoints import look_at

SLANTS = (0.25, 0.5, 0.75, 1.0, 1.1)
"""Radians off square on the plate's side. Rendered at P20 and P14 of the 4 x 6 greenhouse: the
front camera reads the tag from 0.5-0.6 m out up to 1.1 rad (81 deg off-axis at 0.3 m), not
always beyond. A robot dead on the approach pose is kept out of 0.46 m round its centre, with
cost out to 0.51 m (``nav.costmap.robots``, a silent robot): 1.0-1.1 rad clear that."""
FARTHER = 0.1
"""Metres beyond the approach distance of the second ring of looks: the wrist's IK look
(``mission.patrol.inspect_view``) frames the plant from up to 0.6 m out (from 0.65 m it cannot
and the preset frames the pot's side); the rendered wrist frames from 0.6 m at every slant gave
the flower's colour, blooms and pest right at every slant up to 1.1 rad."""


def aside_looks(x: float, y: float, facing: float, standoff: float, grid: CostGrid, here: Pose2D) -> list[Pose2D]:
    """The looks at the pot at (``x``, ``y``) whose plate faces ``facing``, from beside its
    approach pose (``standoff`` out, square on), where the robot fits; nearest ``here`` first."""
    out = []
    for out_to in (standoff, standoff + FARTHER):
        for slant in (0.0, *SLANTS) if out_to > standoff else SLANTS:
            for hand in ((1.0, -1.0) if slant else (1.0,)):
                look = look_at(x, y, facing + hand * slant, 0, grid, out_to)
                if look is not None:
                    out.append(Pose2D(look.x, look.y, look.yaw))
    return sorted(out, key=lambda p: math.hypot(p.x - here.x, p.y - here.y))


def aside_detail(ideal: Pose2D, here: Pose2D, why: str) -> str:
    """The report's words for a pot inspected from ``here`` instead of its approach pose ``ideal``."""
    off = compose(inverse(ideal), here)
    return (f"something stood on its approach pose ({why}): inspected from {math.hypot(off.x, off.y):.2f} m off it, "
            f"turned {abs(math.degrees(off.yaw)):.0f} deg")


__all__ = ["FARTHER", "SLANTS", "aside_detail", "aside_looks"]
