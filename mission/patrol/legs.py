"""A patrol longer than one battery, as legs out from the dock (issue 31).

:class:`Legs` is the tree's composite for the pots: it runs one *leg* at a time, a subtree over
the pots not yet done in a fresh order from where the robot stands, whose pots each begin with
the energy check (``mission.patrol.energy``). A leg ends when its pots are done (the composite
succeeds), when a pot's check fails, or when the check on the way (a pack falling faster than
the model said) fails: the running pot is stopped (its goal cancelled; it is done again in a
later leg, from its approach), and the composite runs the *way home*: drive to the dock, then,
when the dock charges and legs are left, wait on it until the pack is charged, and start the
next leg. When the robot may not charge (``--no-charge``), has used its legs (``--max-legs``),
or the dock does not charge it, the composite succeeds with the reason noted and the patrol
ends ``battery_low`` at the dock, the rest ``skipped``.

:class:`LegLog` keeps each leg for the report (``legs``: when it left and came back, the charge
then, why it came home, when it was charged and to what) and the history.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Iterator, Protocol

from py_trees.behaviour import Behaviour
from py_trees.common import Status
from py_trees.composites import Composite

from mission.patrol.energy import EnergyBudget


@dataclass
class Leg:
    left_s: float
    charge_left: float | None
    pots: int = 0
    headed_home_s: float | None = None
    returned_s: float | None = None
    charge_returned: float | None = None
    why_home: str = ""
    charged_s: float | None = None
    charge_after: float | None = None

    def as_json(self, k: int) -> dict:
        out = {"leg": k, "left_s": round(self.left_s, 1), "charge_left": _share(self.charge_left), "pots": self.pots,
               "returned_s": None if self.returned_s is None else round(self.returned_s, 1),
               "charge_returned": _share(self.charge_returned)}
        if self.why_home:
            out.update(headed_home_s=round(self.headed_home_s, 1), why_home=self.why_home)
        if self.charged_s is not None:
            out.update(charged_s=round(self.charged_s, 1), charge_after=_share(self.charge_after))
        return out


def _share(value: float | None) -> float | None:
    return None if value is None else round(value, 4)


@dataclass
class LegLog:
    """The legs of one patrol; ``now`` is seconds since the patrol began, ``charge`` the pack's."""
    now: Callable[[], float]
    charge: Callable[[], float | None]
    legs: list[Leg] = field(default_factory=list)

    def left(self) -> None:
        self.legs.append(Leg(self.now(), self.charge()))

    def pot_done(self) -> None:
        if self.legs:
            self.legs[-1].pots += 1

    def heading_home(self, why: str) -> None:
        if self.legs and not self.legs[-1].why_home:
            self.legs[-1].why_home, self.legs[-1].headed_home_s = why, self.now()

    def returned(self) -> None:
        """On the dock: the open leg's return (once)."""
        if self.legs and self.legs[-1].returned_s is None:
            self.legs[-1].returned_s, self.legs[-1].charge_returned = self.now(), self.charge()

    def charged(self) -> None:
        self.legs[-1].charged_s, self.legs[-1].charge_after = self.now(), self.charge()

    @property
    def charges(self) -> int:
        return sum(leg.charged_s is not None for leg in self.legs)

    def as_json(self) -> list[dict]:
        return [leg.as_json(k) for k, leg in enumerate(self.legs, 1)]


class LegPlan(Protocol):
    """What :class:`Legs` asks the patrol tree for."""

    def leg(self) -> Behaviour | None:
        """The next leg over the pots not done, in a fresh order from here; None: none left."""

    def gate_failed(self) -> str:
        """Why the leg's last pot check sent the robot home ('' if none did)."""

    def short(self) -> str:
        """'' while the robot can reach the dock above the reserve from where it is."""

    def way_home(self, why: str) -> tuple[Behaviour, bool]:
        """The subtree that takes the robot home after ``why``, and whether it charges there
        (False: the patrol ends at the dock)."""


class Legs(Composite):
    """Runs the plan's legs, and the way home (and the charge) between them."""

    def __init__(self, name: str, plan: LegPlan, log: LegLog):
        super().__init__(name)
        self.plan, self.log = plan, log
        self.phase = ""
        """'out' on a leg, 'home' on the way home to charge, 'last' on the way home to stop."""

    def _run(self, child: Behaviour, phase: str) -> None:
        for old in list(self.children):
            if old.status is not Status.INVALID:
                old.stop(Status.INVALID)
            self.remove_child(old)
        self.add_child(child)
        self.current_child, self.phase = child, phase

    def _next_leg(self) -> bool:
        leg = self.plan.leg()
        if leg is None:
            return False
        self.log.left()
        self._run(leg, "out")
        return True

    def _head_home(self, why: str) -> None:
        self.log.heading_home(why)
        home, charges = self.plan.way_home(why)
        self._run(home, "home" if charges else "last")

    def tick(self) -> Iterator[Behaviour]:
        if not self.children and not self._next_leg():
            self.stop(Status.SUCCESS)
            yield self
            return
        if self.phase == "out":
            why = self.plan.short()
            if why:
                self._head_home(why)
        child = self.children[0]
        for node in child.tick():
            yield node
        if child.status is Status.RUNNING:
            self.status = Status.RUNNING
            yield self
            return
        if self.phase == "out" and child.status is Status.FAILURE:
            self._head_home(self.plan.gate_failed() or "a pot's energy check failed")
        elif self.phase == "home" and child.status is Status.SUCCESS and self._next_leg():
            pass
        else:  # every pot done, or the end at the dock
            self.stop(Status.SUCCESS)
            yield self
            return
        self.status = Status.RUNNING
        yield self

    def stop(self, new_status: Status = Status.INVALID) -> None:
        """An interrupt (the e-stop, a pause) stops the running subtree; the next tick runs the
        same phase again from its start (done pots stay done)."""
        current = self.current_child
        super().stop(new_status)
        if new_status is Status.INVALID:
            self.current_child = current


@dataclass
class LegsSection:
    """The report's ``legs`` and ``energy`` (a ``mission.patrol.report`` observer); each pot
    recorded counts to its leg and tells the budget how long a pot takes."""
    log: LegLog
    budget: EnergyBudget

    def recorded(self, pot, entry: dict, kinds: list[str]) -> None:
        self.log.pot_done()
        self.budget.pot_done()

    def sections(self) -> dict:
        return {"legs": self.log.as_json(), "energy": {**self.budget.figures(), "charges": self.log.charges}}

    def finished(self, doc: dict) -> None:
        pass
