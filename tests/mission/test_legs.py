"""The legs composite (mission.patrol.legs) on a made-up plan: a leg whose pot check fails goes
home, charges, and the next leg does the rest; the way home without a charge ends it."""
from __future__ import annotations

from py_trees.common import Status
from py_trees.composites import Sequence

from behaviours.steps import Check, Do, WaitUntil
from mission.patrol.legs import LegLog, Legs


class Plan:
    """Pots 'a'..'d'; the first leg's charge lasts two pots; charging takes three ticks."""

    def __init__(self, charges: bool = True):
        self.left, self.charges, self.legs, self.t = ["a", "b", "c", "d"], charges, 0, 0
        self.charge, self.ticks_charging = 1.0, 0

    def leg(self):
        if not self.left:
            return None
        self.legs += 1
        budget = [2]

        def pot(name):
            def enough() -> bool:
                budget[0] -= 1
                return budget[0] >= 0 or self.legs > 1

            return Sequence(f"{name} (energy)", memory=True,
                            children=[Check(f"charge for {name}", enough), Do(name, lambda: self.left.remove(name))])

        return Sequence(f"leg {self.legs}", memory=True, children=[pot(p) for p in list(self.left)])

    def gate_failed(self) -> str:
        return "the reserve"

    def short(self) -> str:
        return ""

    def way_home(self, why):
        def charging() -> bool:
            self.ticks_charging += 1
            return self.ticks_charging >= 3

        home = Do("drive home", lambda: None)
        if not self.charges:
            return home, False
        return Sequence("home to charge", memory=True, children=[home, WaitUntil("charging", charging)]), True


def run(plan: Plan) -> tuple[Legs, LegLog, int]:
    clock = [0.0]
    log = LegLog(lambda: clock[0], lambda: plan.charge)
    legs = Legs("pots", plan, log)
    ticks = 0
    while legs.status is not Status.SUCCESS and ticks < 50:
        clock[0] += 1.0
        legs.tick_once()
        ticks += 1
    return legs, log, ticks


def test_a_leg_out_of_charge_goes_home_charges_and_the_next_leg_does_the_rest():
    plan = Plan()
    legs, log, ticks = run(plan)
    assert legs.status is Status.SUCCESS and plan.left == [] and plan.legs == 2
    first, second = log.as_json()
    assert first["pots"] == 0 and first["why_home"] == "the reserve"  # pots count as the report records them
    assert second["left_s"] > first["headed_home_s"] and log.charges == 0  # the plan itself stamps returns/charges


def test_without_a_charge_the_patrol_ends_after_the_way_home_with_pots_left():
    plan = Plan(charges=False)
    legs, log, _ = run(plan)
    assert legs.status is Status.SUCCESS and plan.left == ["c", "d"] and plan.legs == 1 and len(log.legs) == 1
