"""The patrol tree's legs (``mission.patrol.legs.LegPlan``, issue 31): what each leg holds, the
energy check before each pot and on the way, and the way home: to the dock and charge there, to
the dock to end the patrol, or, when the dock is out of reach, out of the aisles
(``mission.patrol.parking``).

A leg is the pots not done, in the mission's order from where the robot stands (the first leg
in the order planned at the start, each later one in a fresh shortest order from the dock), each
pot behind its check (``mission.patrol.energy``). Ending the patrol for want of charge (no
charger, the legs used, a dock that gives no current, a pot out of reach of a full charge, the
dock out of reach) notes ``battery`` with the pots left: the outcome is then ``battery_low``.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from py_trees.behaviour import Behaviour
from py_trees.composites import Selector, Sequence

from behaviours.steps import Check, Do, WaitUntil
from hw.odometry import Pose2D
from mission.patrol.mission_file import MissionPot
from mission.patrol.parking import parking_spot

if TYPE_CHECKING:
    from mission.patrol.tree import PatrolTree


def later_label(pot_id: str, go: int) -> str:
    """The tree's name for ``pot_id``'s go number ``go``: ``P01``, ``P01 later``, ``P01 later 2``."""
    return pot_id if go == 0 else f"{pot_id} later" + (f" {go}" if go > 1 else "")


class PatrolLegs:
    """The legs of one patrol tree; ``Legs`` asks it for each leg and each way home."""

    def __init__(self, tree: "PatrolTree"):
        self.tree = tree
        self._gate_why = ""
        self._next_check = 0.0
        self._on_dock_since = 0.0
        self.parked: Pose2D | None = None
        """Where the robot stopped, clear of the aisles, when it could not reach the dock."""
        self._stranded, self._next_reach = False, 0.0

    def _park(self, why: str) -> Sequence:
        """Out of the aisles and clear of their mouths (``mission.patrol.parking``), for a robot
        that cannot reach its dock; the note says where it stands."""
        spot: list[Pose2D] = []

        def choose() -> str | None:
            here = self.tree.nav.map_pose()
            found = parking_spot(self.tree.nav.global_costmap.grid, (here.x, here.y), self.tree.energy.lengths)
            if found is None:
                return "no place clear of the aisles within reach"
            spot[:] = [Pose2D(found[0], found[1], here.yaw)]
            return None

        def parked() -> None:
            here = self.tree.nav.map_pose()
            self.parked = here
            where = ("stopped clear of the aisles" if "park_spot" not in self.tree.notes
                     else f"could not get clear of the aisles ({self.tree.notes['park_spot']}): stopped")
            self._battery_end(f"{why}; the dock is out of reach: {where} at ({here.x:.1f}, {here.y:.1f}) in the map, "
                              f"{self.tree.energy.charge or 0.0:.0%} left")

        go = Sequence("park", memory=True, children=[Do("choose a spot clear of the aisles", choose),
                                                      self.tree._drive("drive clear of the aisles", lambda: spot[0])])
        return Sequence("stop clear of the aisles", memory=True, children=[
            self.tree._or_note("clear of the aisles", go, lambda reason: self.tree.notes.__setitem__("park_spot", reason)),
            Do("parked", parked)])

    def leg(self) -> Behaviour | None:
        """The next leg: the pots not done, each after its energy check; the first leg in the
        order planned at the start, each later one in a fresh order from the dock."""
        left = [p for p in self.tree.mission.pots if not self.tree.visits[p.id].done]
        if not left:
            return None
        if self.tree.legs.legs:
            self.tree.order = self.tree._order(left)
        self._gate_why = ""
        order = [p for p in self.tree.order if not self.tree.visits[p.id].done]
        goes = range(self.tree.config.later_goes + 1)
        return Sequence(f"leg {len(self.tree.legs.legs) + 1}", memory=True,
                        children=[self._gated(p, go) for go in goes for p in order])

    def _gated(self, pot: MissionPot, go: int = 0) -> Sequence:
        """``pot``'s go number ``go`` (0: its first), after its energy check."""
        visit = self.tree.visits[pot.id]

        def enough() -> bool:
            if visit.done or (go and not visit.deferred):
                return True
            here, goal = self.tree.nav.map_pose(), self.tree.approach_goal(pot)
            why = self.tree.energy.check_pot((here.x, here.y), (goal.x, goal.y))
            if why:
                self._gate_why = f"before {pot.id}: {why}"
            return not why

        label = later_label(pot.id, go)
        return Sequence(f"{label} (energy)", memory=True,
                        children=[Check(f"charge for {label}", enough), self.tree._pot(pot, go)])

    def gate_failed(self) -> str:
        return self._gate_why

    def short(self) -> str:
        now = self.tree.clock.now()
        if now < self._next_check:
            return ""
        self._next_check = now + self.tree.config.energy.check_every
        here = self.tree.nav.map_pose()
        return self.tree.energy.check_home((here.x, here.y))

    def way_home(self, why: str) -> tuple[Behaviour, bool]:
        """To the dock, then charge there; or, when it may not charge (``--no-charge``, the
        legs used, a full charge that did not reach one pot), to the dock to end the patrol."""
        e, legs = self.tree.config.energy, self.tree.legs.legs
        self.tree.energy.why_home = why
        stop = ""
        if not e.charge:
            stop = "the dock does not charge (--no-charge)"
        elif e.max_legs is not None and len(legs) >= e.max_legs:
            stop = f"{len(legs)} leg(s) done, the most allowed (--max-legs)"
        elif legs and legs[-1].pots == 0 and len(legs) > 1:
            stop = "a full charge did not reach one more pot"
        here = self.tree.nav.map_pose()
        if not self.tree.energy.reachable((here.x, here.y)):
            return self._park(why), False
        self._stranded, self._next_reach = False, 0.0
        to_dock = [Selector("to the dock", memory=False, children=[
            Sequence("stranded", memory=True, children=[Check("dock out of reach?", self._out_of_reach),
                                                        self._park(why)]),
            Selector("drive or park", memory=True, children=[
                Sequence("drive to the dock", memory=True, children=[self.tree._to_dock("drive to the dock"),
                                                                     Do("on the dock", self._docked)]),
                self._park(why)])])]
        if stop:
            self._battery_end(f"{why}; {stop}")
            return Sequence("home to stop", memory=True, children=to_dock), False
        charged = WaitUntil(f"charging to {e.charge_to:.0%}",
                            lambda: self.tree.energy.charge is not None and self.tree.energy.charge >= e.charge_to,
                            self._not_charging)
        return Sequence("home to charge", memory=True, children=[*to_dock, charged, Do("charged", self._charged)]), True

    def _out_of_reach(self) -> bool:
        """Latched, checked every ``check_every`` s on the way home: the pack no longer holds the
        way to the dock (it kept falling faster than the model said)."""
        now = self.tree.clock.now()
        if not self._stranded and now >= self._next_reach:
            self._next_reach = now + self.tree.config.energy.check_every
            here = self.tree.nav.map_pose()
            self._stranded = not self.tree.energy.reachable((here.x, here.y))
        return self._stranded

    def _battery_end(self, why: str) -> None:
        left = [p.id for p in self.tree.mission.pots if not self.tree.visits[p.id].done]
        self.tree.notes["battery"] = f"{why}: the patrol ends at the dock with {len(left)} pot(s) left ({', '.join(left)})"

    def _docked(self) -> None:
        self.tree.legs.returned()
        self._on_dock_since = self.tree.clock.now()

    def _charged(self) -> None:
        self.tree.legs.charged()
        self.tree.energy.why_home = ""

    def _not_charging(self) -> str | None:
        """Why waiting on the dock is pointless: no current into the pack for a while."""
        now = self.tree.clock.now()
        if self.tree.energy.charging:
            self._on_dock_since = now
            return None
        if now - self._on_dock_since < self.tree.config.energy.charge_start_timeout:
            return None
        why = f"no current into the pack for {self.tree.config.energy.charge_start_timeout:g} s on the dock: not charging"
        self._battery_end(why)
        return why
