"""The fleet benches' head-on judge (``lupin.bench.fleet_patrol.FleetJudge``): two robots in one
aisle closing on each other meet once however long they close; a robot standing still, however
it jitters in the physics, meets no one (``fleet.handover``'s dead r2 counted 27 meetings)."""
from __future__ import annotations

from types import SimpleNamespace

from fleet.aisles import NO_AISLE
from lupin.bench.fleet_patrol import SMALL, FleetJudge, greenhouse


class Scene:
    def __init__(self):
        self.where: dict[str, tuple[float, float]] = {}

    def truths(self):
        return {n: SimpleNamespace(x=x, y=y) for n, (x, y) in self.where.items()}


def judged(moves) -> int:
    """Head-on meetings over ``moves``: per sample, each robot's (x, y)."""
    scene = Scene()
    judge = FleetJudge(scene, greenhouse(SMALL))
    for where in moves:
        scene.where = where
        judge.sample()
    return judge.head_on


def test_two_robots_closing_in_one_aisle_meet_once_and_a_robot_standing_still_meets_no_one():
    judge = FleetJudge(Scene(), greenhouse(SMALL))
    [a], [b] = judge.aisles.at([3.0], [1.5]), judge.aisles.at([4.2], [1.5])
    assert a == b != NO_AISLE  # both between the first two rows
    closing = [{"r1": (3.0 + 0.03 * k, 1.5), "r3": (4.2 - 0.03 * k, 1.5)} for k in range(10)]
    assert judged(closing) == 1
    jitter = [{"r1": (3.0 + 0.03 * k, 1.5), "r2": (4.2 + (-1) ** k * 0.0004, 1.5)} for k in range(10)]
    assert judged(jitter) == 0
