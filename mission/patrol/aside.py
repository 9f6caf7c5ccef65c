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
from typing import TYPE_CHECKING

from py_trees.behaviour import Behaviour
from py_trees.composites import Selector, Sequence

from behaviours.search import SearchTag
from behaviours.steps import Check
from behaviours.visit import PotVisit
from behaviours.why import why
from hw.odometry import Pose2D
from mission.patrol.mission_file import MissionPot
from nav.costmap.grid import INSCRIBED, UNKNOWN, CostGrid
from nav.frames import compose, inverse
from nav.viewpoints import look_at

if TYPE_CHECKING:
    from mission.patrol.tree import PatrolTree

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


def beside_branch(tree: "PatrolTree", pot: MissionPot, visit: PotVisit, approach: Behaviour, taken: list[str]) -> Sequence:
    """The pot's branch for when ``approach`` failed and something stands on its goal (its cell
    is inscribed or lethal in the global costmap now): the looks beside it, until one reads the
    pot's own tag standing there; the visit then says where it stood and why. ``taken`` gets
    why the approach failed, and why the looks did (their leaves' own words are gone once the
    selector above them moves on)."""
    c, nav, standoff = tree.config, tree.nav, tree.mission.standoff

    def goal_taken() -> bool:
        goal = tree.approach_goal(pot)
        taken[:] = [why(approach)]
        return INSCRIBED <= int(nav.global_costmap.grid.cost_at(goal.x, goal.y)) < UNKNOWN

    def looks() -> list[Pose2D]:
        x, y, facing = tree.finder.where(pot, visit)
        return aside_looks(x, y, facing, standoff, nav.global_costmap.grid, nav.map_pose())

    def found(reads, robot: Pose2D) -> bool:
        ideal = tree.approach_goal(pot)
        if not tree.finder.place(pot, visit, reads, robot, c.tag_max_distance):
            return False
        visit.aside = aside_detail(ideal, robot, taken[0])
        return True

    def not_seen() -> bool:
        taken.append(f"its approach pose is taken, and the looks beside it did not read its tag ({why(timed)})")
        return False

    search = SearchTag(f"look beside {pot.id}", nav, looks, tree.cameras["front"], tree.tag_reader, found,
                       tree.clock, c.settle, c.search_look_timeout, on_the_way=False)
    timed = tree._timed(search, c.search_time)
    return Sequence(f"beside {pot.id}", memory=True, children=[
        Check(f"{pot.id} approach pose taken?", goal_taken),
        Selector(f"look beside {pot.id}", memory=True, children=[timed, Check(f"{pot.id} not read beside", not_seen)])])


__all__ = ["FARTHER", "SLANTS", "aside_detail", "aside_looks", "beside_branch"]
