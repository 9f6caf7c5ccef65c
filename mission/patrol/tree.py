"""The patrol as a py_trees tree: guards, start-up gate, one branch per pot, then home.

::

    Lupin patrol                              Hold: while the e-stop is engaged or latched
      lidar lost                                Hold: no trustworthy scan for 3 s (mission.patrol.lidar_loss)
      operator pause                            Hold: while the operator has paused
        mission                                   Selector, priorities re-checked every tick
          battery low                               Sequence: power-low (latched) > go home
            battery low?                              the seed's policy: 20 s below 11.1 V
            go home                                   return home, park arm (as at the end)
          patrol                                    Sequence
            start-up                                  OneShot > Timeout(patrol.startup_timeout)
              heal controllers                          the boot heal, one non-blocking pass
              navigation ready                          the readiness cascade (scans, map, transform)
              arm to travel                             Selector: the arm's travel pose, or note it
            pots and tags                             Parallel: ends when the pots do
              pots                                      Legs: a leg, home (and charge), the next leg
                leg 1                                     Sequence over the pots not done, in order
                  P01 (energy)                              Sequence: the energy check, then the pot
                  charge for P01                            enough for the pot, the way back, the reserve
                P01                                       OneShot: a finished pot is never redone
                  visit P01                                 Selector: inspect, or record it failed
                    inspect P01                               Sequence
                      get to P01                                Selector
                        approach P01                              Retry(retries) > Timeout > NavigateTo
                        beside P01                                its goal taken: the looks beside it
                                                                  until one reads its tag
                      front camera P01                          ReadTags, or note no frame
                      find P01                                  Selector: a tag there, or search for it
                      moved P01                                 Selector: in place, or approach again
                                                                (closely: where its tag put a moved
                                                                pot, or where a far stop missed it)
                      wrist P01                                 arm to inspect_plant (or aim) > DetectFlower,
                                                                or note what failed
                      record P01
                      stow arm P01                              arm to travel, or note it
                    P01 failed                                defers the pot (someone may be in the
                                                              way); on its last go, records it
                                                              failed (unreachable)
                ...
                P01 later                                 OneShot: only a deferred pot, once more
                ...
                P01 later 2                               ... and so on, ``patrol.later_goes`` rounds
                ...
              watch tags                                tags read en route (discovered_tags)
            finish                                    return home (or note), park arm (or note)

The guards (``behaviours.guard.Hold``, ``mission.patrol.holds``): the e-stop has priority over
everything; when it engages, the running leaves are stopped, which cancels the navigation goal
and holds the arm, and nothing moves again until the operator's ``resume`` after the release.
Then the tree is ticked again: ``OneShot`` keeps the start-up gate and every finished pot done,
so the patrol continues with the pot in progress, from its approach. Power-low aborts the
patrol for the trip home (outcome ``battery_low``); a pause holds like the e-stop but needs no
release. A lost lidar (no trustworthy scan for ``patrol.lidar_lost_after``) holds the same way
until scans return, and past ``patrol.lidar_lost_give_up`` ends the patrol ``aborted``
(``mission.patrol.lidar_loss``). A paused robot does not drive home on power-low until resumed: the operator who paused
it is in charge.

In a fleet (the mission came with the fleet's aisles, and the link joins a router) every drive
first asks for the aisles on its way (``behaviours.aisles.EnterAisles``, the gate
``mission.patrol.aisle_gate``), a leaf beside the pots lets go of those behind, and the finish
lets go of all; a robot alone has no gate and its tree is exactly the one above.

Pots are found where they are (``mission.patrol.pot_finder``): the tag read at arrival places
the pot; a pot off the mission's pose is approached again from where it is and reported
``moved``; with no tag where the pot should be, the pots the map shows nearby are looked at for
it before it is ``not_found``. A pot whose approach pose something else stands on (a robot that
died there, a cart) is inspected from a look beside it that reads its tag
(``mission.patrol.aside``).

The pots run in legs out from the dock (``mission.patrol.legs``): before each pot the energy
budget (``mission.patrol.energy``) checks that the pot and the way back leave the reserve on
the dock, and on the way that the dock is still within reach; when not, the robot goes home,
charges, and does the pots left in a fresh order from the dock.

A pot the robot could not get to is tried again after the others (its ``later`` branches, one
round each), then recorded failed; the patrol goes on: every pot branch succeeds. Only the start-up
gate (heal, readiness) can fail the tree. The tag is read first, right at arrival, while the arm
is still in its travel pose (the front camera does not need the arm).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import py_trees
from py_trees.behaviour import Behaviour
from py_trees.common import OneShotPolicy, ParallelPolicy, Status
from py_trees.composites import Parallel, Selector, Sequence
from py_trees.decorators import OneShot, Retry

from arm.presets import preset
from behaviours.aisles import EnterAisles, LetGoBehind
from behaviours.arm import MoveArm
from behaviours.guard import Hold
from behaviours.navigate import NavigateTo
from behaviours.perceive import DetectFlower, ReadTags, WatchTags
from behaviours.search import SearchTag
from behaviours.why import why
from behaviours.steps import Check, Do, WaitUntil
from behaviours.timeout import Timeout
from behaviours.visit import PotVisit
from hw.interfaces import Clock
from hw.odometry import Pose2D
from mission.patrol.aisle_gate import RETRY, AisleGate
from mission.patrol.aside import beside_branch
from mission.patrol.config import PatrolConfig
from mission.patrol.energy import EnergyBudget
from mission.patrol.legs import LegLog, Legs, LegsSection
from mission.patrol.holds import MissionHolds
from mission.patrol.inspect_view import InspectView
from mission.patrol.lidar_loss import LidarLoss
from mission.patrol.mission_file import Mission, MissionPot
from mission.patrol.leg_plan import PatrolLegs, later_label
from mission.patrol.pot_finder import PotFinder
from mission.patrol.visit_order import visit_order
from nav.path_lengths import lengths_from, path_lengths
from mission.patrol.report import PatrolReport
from mission.runtime.heal import heal_controllers
from mission.runtime.robot import Robot
from nav.frames import distance
from nav.navigator import Navigator
from perception.camera_pipeline import CameraPipeline
from perception.flower_detector import FlowerDetector
from perception.tag_reader import TagReader

HOME_TRIES = 5
"""Attempts at the drive home (``nav_timeout`` each), more than a pot's ``retries``: a pot not
reached is tried again later, but a robot not home is left standing in an aisle, in the growers'
way (safety.people seed 1, 1,725-1,845 s: its two minutes went on a cart and a crossing walker,
and the second try ran out 1.6 m from the dock, driving)."""


@dataclass
class PatrolTree:
    """The tree and what its leaves share; ``root`` ticks on the runtime's scheduler."""

    mission: Mission
    robot: Robot
    nav: Navigator
    cameras: dict[str, CameraPipeline]
    report: PatrolReport
    tag_reader: TagReader
    config: PatrolConfig = field(default_factory=PatrolConfig)
    visits: dict[str, PotVisit] = field(default_factory=dict)
    order: list[MissionPot] = field(default_factory=list)
    notes: dict[str, str] = field(default_factory=dict)
    """Steps outside any pot that failed without failing the patrol ('arm', 'home', 'park') ->
    why, and 'battery' when power-low sent the robot home. The patrol goes on without the arm;
    not getting home makes the outcome ``failed``."""
    holds: MissionHolds | None = None
    """The e-stop latch and the pause (default: on the robot's e-stop bridge)."""
    gate: AisleGate | None = None
    """A fleet's aisle locks (None: a robot alone, no aisle is asked for)."""
    root: Behaviour | None = None

    def __post_init__(self) -> None:
        self.finder = PotFinder(self.mission, self.nav, self.config)
        self.view = InspectView(self.robot.config.arm, self.config)
        self.detector = FlowerDetector(self.robot.config.perception.flower)
        home = self.mission.home
        self.energy = EnergyBudget(self.config.energy, self.robot.config.sim.battery, self.robot.config.nav.mppi.vx_max,
                                   (home.x, home.y), self._lengths_from)
        self.legs = LegLog(lambda: self.clock.now() - self.report.t0, lambda: self.energy.charge)
        self.report.observers.append(LegsSection(self.legs, self.energy))
        self.order = self._order(self.mission.pots)
        self.visits = {p.id: PotVisit(p.id) for p in self.order}
        self.plan = PatrolLegs(self)
        if self.holds is None:
            self.holds = MissionHolds(self.robot.estop, self.clock.now, self.report.t0)
        self.lidar = LidarLoss(lambda: self.robot.monitor.untrusted_since, self.clock.now,
                               self.config.lidar_lost_after, self.config.lidar_lost_give_up,
                               armed=lambda: self.nav.readiness.active)
        self.nav.keep_out = None if self.gate is None else self.gate.keep_out
        if self.gate is not None:
            self.report.observers.append(self.gate)  # the report's ``aisles``: the waits for them
        self.root = self._build()

    @property
    def clock(self) -> Clock:
        return self.robot.scheduler.clock

    def _order(self, pots: list[MissionPot]) -> list[MissionPot]:
        """``pots`` in the mission's order from where the robot stands."""
        here = self.nav.map_pose()
        return visit_order(self.mission.model_copy(update={"pots": pots}), (here.x, here.y),
                           lambda points: path_lengths(self.nav.global_costmap.grid, points))

    def _lengths_from(self, origin: tuple[float, float], points: np.ndarray) -> np.ndarray:
        """The planner's path lengths from ``origin`` to ``points`` over the whole map (its
        corners are taken in: the way home may leave the box round the two ends, through a
        doorway at the greenhouse's far side)."""
        grid = self.nav.global_costmap.grid
        x0, x1, y0, y1 = grid.geometry.extent
        corners = np.array([[x0, y0], [x1, y1]])
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        return lengths_from(grid, origin, np.vstack([points, corners]))[:len(points)]

    # --- goals ---------------------------------------------------------------------------
    def approach_goal(self, pot: MissionPot) -> Pose2D:
        """Where to stand for the pot: the mission's approach pose, or, once its tag has shown it
        moved, the approach pose from where it is."""
        return self.finder.approach(pot, self.visits[pot.id])

    def inspect_goal(self, pot: MissionPot, visit: PotVisit) -> tuple[object, str]:
        """The patrol's inspect preset from the ideal approach pose; from elsewhere, the IK pose
        that looks at the spot it would have framed (``mission.patrol.inspect_view``). Where the
        robot is, is its belief now, not on arrival: it stands still, and the goal is in the map
        as it is now (a loop closure since arrival moves both)."""
        here = visit.arrived = self.nav.map_pose()
        goal, visit.view = self.view.goal(self.approach_goal(pot), here)
        return goal, visit.view

    # --- building blocks -----------------------------------------------------------------
    def _timed(self, child: Behaviour, duration: float) -> Timeout:
        return Timeout(f"{child.name} (timeout)", child, self.clock, duration)

    def _drive(self, name: str, goal: Callable[[], Pose2D], on_start: Callable[[], None] = lambda: None,
               xy_tolerance: float | None = None, tries: int | None = None) -> Retry:
        """Drive to ``goal``, ``tries`` attempts (the mission's ``retries`` when None)."""
        attempt = self._timed(NavigateTo(name, self.nav, goal, self.clock, on_start, xy_tolerance), self.mission.nav_timeout)
        if self.gate is not None:  # the aisles first, outside the drive's time limit: a wait may be long
            attempt = Sequence(f"{name} (aisles)", memory=True, children=[
                EnterAisles(f"aisles for {name}", self.gate, self.nav, goal, self.clock, self._lengths_from, RETRY), attempt])
        tries = self.mission.retries if tries is None else tries
        return Retry(f"{name} (x{tries})", attempt, tries)

    def _arm(self, name: str, goal: Callable[[], tuple[object, str]]) -> Timeout:
        return self._timed(MoveArm(name, self.robot.arm, goal), self.config.arm_timeout)

    def _or_note(self, name: str, step: Behaviour, note: Callable[[str], None]) -> Selector:
        """``step``, or, when it fails, ``note(why)`` and carry on."""
        return Selector(name, memory=True, children=[step, Do(f"{name}: note failure", lambda: note(why(step)))])

    def _heal(self) -> str | None:
        """The boot heal's controller walk, one non-blocking pass (a manager that does not answer
        is not waited for: the gate fails with the heal's own message)."""
        names = tuple(self.robot.config.hw.controllers)
        healed = heal_controllers(self.robot.controllers, names, self.clock, budget=0.0)
        return None if healed.healed else f"heal: {healed.message}"

    def _travel(self) -> tuple[object, str]:
        return preset(self.config.travel_pose), self.config.travel_pose

    # --- the tree ------------------------------------------------------------------------
    def _battery_low(self) -> bool:
        """Power-low, latched: a pack that recovers under a lighter load is still flat."""
        power = self.robot.power
        if power.state.low and "battery" not in self.notes:
            v = power.reading.voltage if power.reading is not None else float("nan")
            cfg = power.policy.config
            self.notes["battery"] = (f"power low {self.clock.now() - self.report.t0:.1f} s into the patrol ({v:.2f} V, below "
                                     f"{cfg.min_voltage:g} V for {cfg.power_low_time:g} s): patrol aborted, going home")
        return "battery" in self.notes

    @property
    def battery_low(self) -> bool:
        return "battery" in self.notes

    def _finish(self, name: str) -> Sequence:
        """Drive home (when the mission says so) and park the arm, noting what failed."""
        note = self.notes.__setitem__
        steps = [self._or_note("park arm", self._arm("arm to home", lambda: (preset("home"), "home")),
                               lambda reason: note("park", reason))]
        if self.mission.return_home:
            home = Sequence("home", memory=True, children=[self._or_note("return home", self._to_dock("drive home"),
                                                                         lambda reason: note("home", reason)),
                                                           Do("on the dock", self.legs.returned)])
            steps.insert(0, Selector("unless parked", memory=True, children=[
                Check("parked clear of the aisles?", lambda: self.plan.parked is not None), home]))
        if self.gate is not None:
            steps.append(WaitUntil("let go of the aisles", self.gate.backed_out))
        return Sequence(name, memory=True, children=steps)

    def _to_dock(self, name: str) -> Retry:
        home = self.mission.home
        return self._drive(name, lambda: Pose2D(home.x, home.y, home.yaw), tries=HOME_TRIES)


    def _build(self) -> Behaviour:
        c, note = self.config, self.notes.__setitem__
        startup = Sequence("start-up", memory=True, children=[
            Do("heal controllers", self._heal),
            WaitUntil("navigation ready", lambda: self.nav.readiness.active,
                      lambda: self.nav.readiness.overdue(self.clock.now()) and self.nav.readiness.status(self.clock.now())),
            self._or_note("arm to travel", self._arm("arm to travel", self._travel), lambda reason: note("arm", reason)),
        ])
        pots = Legs("pots", self.plan, self.legs)
        watch = WatchTags("watch tags", self.cameras["front"], self.tag_reader,
                          lambda frame, reads: self.report.saw(reads, self.nav.map_pose()),
                          self.nav.map_pose, c.watch_spacing, c.watch_turn)
        beside = [watch] if self.gate is None else [watch, LetGoBehind("let go behind", self.gate, self.nav, self.clock, RETRY)]
        patrol = Sequence("patrol", memory=True, children=[
            OneShot("start-up (once)", self._timed(startup, c.startup_timeout), OneShotPolicy.ON_COMPLETION),
            Parallel("pots and tags", ParallelPolicy.SuccessOnSelected([pots]), children=[pots, *beside]),
            self._finish("finish")])
        battery = Sequence("battery low", memory=True, children=[Check("battery low?", self._battery_low),
                                                                  self._finish("go home")])
        mission = Selector("mission", memory=False, children=[battery, patrol])
        paused = Hold("operator pause", mission, self.holds.pause_reason)
        return Hold("Lupin patrol", Hold("lidar lost", paused, self.lidar.reason), self.holds.estop)

    def _pot(self, pot: MissionPot, go: int = 0) -> Behaviour:
        """The pot's branch for its go number ``go``: 0 its first; from 1 its later goes, each
        round after the other pots, taken only while the goes before failed to get there. In a
        greenhouse people work in, what stops a robot from a pot (someone in the only aisle, a
        cart left on the approach pose) usually moves on: the pot is tried again once everything
        else is done (``patrol.later_goes`` rounds), and recorded failed only then."""
        c, visit = self.config, self.visits[pot.id]
        later, last = go > 0, go >= c.later_goes
        cams, clock = self.cameras, self.clock

        def fail(step: str) -> Callable[[str], None]:
            return lambda reason: visit.failures.__setitem__(step, reason)

        def arrived() -> None:
            visit.arrived = self.nav.map_pose()

        def count() -> None:
            visit.attempts += 1

        approach = self._drive(f"approach {pot.id}", lambda: self.approach_goal(pot), count)

        def read_front(label: str) -> Selector:
            return self._or_note(f"{label} {pot.id}", self._timed(
                ReadTags(f"read tag {pot.id}", cams["front"], self.tag_reader, visit, clock, c.settle), c.frame_timeout),
                fail("front"))

        front = read_front("front camera")
        find = self._find(pot, visit)
        def in_place() -> bool:
            """Not moved, and the robot stopped close enough to its approach pose for the wrist; or
            it stands beside a taken approach pose, where it read the tag (the wrist aims from there)."""
            off = distance(self.nav.map_pose(), self.approach_goal(pot)) if visit.arrived is not None else 0.0
            return bool(visit.aside) or (not visit.moved and off <= c.moved_approach_xy * 1.5)

        again = Selector(f"approach again {pot.id}", memory=True, children=[
            self._timed(NavigateTo(f"approach closely {pot.id}", self.nav, lambda: self.approach_goal(pot), clock,
                                   count, c.moved_approach_xy), self.mission.nav_timeout),
            self._drive(f"approach again {pot.id}", lambda: self.approach_goal(pot), count)])
        moved = Selector(f"moved {pot.id}", memory=True, children=[
            Check(f"in place {pot.id}", in_place),
            Sequence(f"re-approach {pot.id}", memory=True, children=[
                again, Do(f"arrived again {pot.id}", arrived), read_front("front camera again")])])
        inspect = self._arm(f"arm to inspect {pot.id}", lambda: self.inspect_goal(pot, visit))
        look = self._timed(DetectFlower(f"detect flower {pot.id}", cams["wrist"], self.detector, visit, clock, c.settle),
                           c.frame_timeout)

        def note_wrist() -> None:
            if inspect.status is Status.FAILURE:
                visit.failures["arm"] = why(inspect)
            else:
                visit.failures["wrist"] = why(look)

        def pot_failed() -> None:
            reason = "; ".join(taken) or why(approach)
            taken.clear()
            if not last and "search" not in visit.failures:
                visit.deferred, visit.arrived, visit.aside = visit.deferred or reason, None, ""
                visit.failures.clear()
                return
            if "search" not in visit.failures:
                visit.failures.setdefault("approach", reason)
            if not visit.done:
                self.report.record(pot, visit, self.approach_goal(pot))

        wrist = Selector(f"wrist {pot.id}", memory=True, children=[
            Sequence(f"look {pot.id}", memory=True, children=[inspect, look]), Do(f"wrist {pot.id}: note failure", note_wrist)])
        record = Do(f"record {pot.id}", lambda: self.report.record(pot, visit, self.approach_goal(pot)))
        stow = self._or_note(f"stow arm {pot.id}", self._arm(f"arm to travel {pot.id}", self._travel), fail("stow"))
        taken: list[str] = []
        """Why the approach failed, and why the looks beside its taken goal did (its leaves'
        own words are gone once the selector above them moves on)."""
        beside = beside_branch(self, pot, visit, approach, taken)
        inspect_pot = Sequence(f"inspect {pot.id}", memory=True, children=[
            Selector(f"get to {pot.id}", memory=True, children=[approach, beside]),
            Do(f"arrived {pot.id}", arrived), front, find, moved, wrist, record, stow])
        failed = Do(f"{pot.id} failed", pot_failed)
        branch = Selector(f"visit {pot.id}", memory=True, children=[inspect_pot, failed])
        if later:
            branch = Selector(f"{pot.id} later?", memory=True, children=[
                Check(f"{pot.id} done", lambda: not visit.deferred or visit.done), branch])
        return OneShot(later_label(pot.id, go), branch, OneShotPolicy.ON_COMPLETION)

    def _find(self, pot: MissionPot, visit: PotVisit) -> Selector:
        """The pot's own tag placed the pot (or it has none to look for, or another tag is
        there: a tag_mismatch); else search the pots the map shows nearby, noting a miss."""
        c, finder = self.config, self.finder

        def placed() -> bool:
            if finder.needs_search(pot, visit):
                return False
            if visit.arrived is not None:
                finder.place(pot, visit, visit.tags, self.nav.map_pose(), c.tag_max_distance)
            return True

        def found(reads, robot: Pose2D) -> bool:
            return finder.place(pot, visit, reads, robot, self.robot.config.survey.found_read)

        search = SearchTag(f"search {pot.id}", self.nav, lambda: finder.search_looks(pot), self.cameras["front"],
                           self.tag_reader, found, self.clock, c.settle, c.search_look_timeout)

        timed = self._timed(search, c.search_time)

        def not_found() -> bool:
            visit.failures["search"] = (f"tag {pot.tag} not found within {c.search_radius:g} m of the mission's "
                                        f"position ({why(timed)})")
            return False

        return Selector(f"find {pot.id}", memory=True, children=[
            Check(f"tag at {pot.id}", placed), timed, Do(f"not found {pot.id}", not_found)])

    # --- reading it ----------------------------------------------------------------------
    def current_step(self) -> str:
        """The running leaf of the patrol proper (not the tag watcher beside it): the progress
        display's 'current step'."""
        node = self.root
        while node is not None and node.children:
            if isinstance(node, Hold) and node.reason:
                return node.reason
            node = next((c for c in node.children if c.status is Status.RUNNING and not isinstance(c, (WatchTags, LetGoBehind))), None)
        return node.name if node is not None else ""

    def pots_done(self) -> int:
        """How many pots are finished (recorded)."""
        return sum(v.done for v in self.visits.values())

    def failure(self) -> str:
        """Why the tree failed (empty while it has not)."""
        return why(self.root) if self.root.status is Status.FAILURE else ""

    def render(self) -> str:
        return py_trees.display.unicode_tree(self.root, show_status=True)
