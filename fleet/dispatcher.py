"""The fleet patrol's dispatcher: split a mission between the robots up, send each its part,
follow them to the end, hand a lost robot's pots to the others (spec/fleet.md "The fleet patrol").

It is a member of the fleet like a console (one Zenoh session to the router as ``dispatcher``)
and talks to the robots through their ordinary link only: ``mission_start`` with each robot's
part as an ordinary patrol (``fleet.assign``: its pots in its own map frame, the mission's name
shared, so each robot's report and history rows are its own), their telemetry to follow them,
and the ``report`` query for each robot's report.json. It hosts the aisle locks' arbiter
(``fleet.aisle_locks.AisleLockServer``) for as long as it runs, and sends each robot the aisles'
outlines with its patrol (found on the split's map, in the robot's own frame), so the robot asks
for an aisle before it enters (``mission.patrol.aisle_gate``).

Following a robot: a patrol has ended when the report the robot answers has an outcome (its
telemetry saying ``done`` only asks sooner). While it runs, its report is fetched whenever its
telemetry shows a pot inspected that the last fetch did not have, and every ``REPORT_EVERY`` s,
so a robot that dies leaves the report as it last wrote it (rewritten after every pot), short
at most of the pot it finished as it died.

A robot drops out when its liveliness goes (the roster; away ``LOST_AFTER`` s), when its e-stop is
held longer than ``fleet.handover_after`` s of its own clock while another robot could go on
(a fleet e-stop, every robot stopped, hands nothing over: ``resume`` goes on where they were),
or when its battery runs low. A robot stopped is sent ``mission_abort`` (its report then ends
``aborted``). A robot whose battery runs low is not: its own patrol takes it home (``battery_low``,
mission.patrol.tree: power low, or the energy budget's charge too short for the pots left) and
its pots go once that patrol has ended so; aborted, it would stand flat where it was, in an aisle
perhaps. Its unfinished pots (assigned and not ``inspected`` in its last report) are split
between the others that are up and not stopped, from their docks, and each gets its share as a
*further patrol* once its current one has ended (a running patrol cannot take more pots; each
patrol ends at its dock, so the split from the docks is the right one). The dispatcher is done
when no robot is on patrol and nothing waits to be sent.
"""
from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import numpy as np
import zenoh

from fleet.aisle_locks import AisleLockServer
from fleet.aisles import find_aisles, outlines
from fleet.assign import Pose, assign
from fleet.fleet_report import RobotRun, write_fleet_report
from hw.atomic_file import write_atomic
from hw.errors import InputError
from hw.odometry import Pose2D
from mission.link.client import LinkClient
from mission.link.roster import Roster
from mission.patrol.mission_file import Mission
from nav.costmap.grid import CostGrid
from nav.frames import compose
from nav.occupancy import OccupancyMap

REPORT_EVERY = 5.0
"""Wall seconds between fetches of a patrolling robot's report: a lost robot's last report is at
most this old (a pot takes ~6 s of robot time, a few times that in the sim's fast wall time)."""
POLL = 0.2
"""Wall seconds between looks at the robots' telemetry (their fast beat is 10 Hz)."""
LOST_AFTER = 10.0
"""Wall seconds a robot's liveliness token must stay away before its pots are handed over:
handing a live robot's pots over costs a patrol done twice, and tokens lapse without a robot
dying: a Wi-Fi roam on a farm, or a machine stalled past the robots' 800 ms lease (every token
drops at once and comes back as soon as it goes on, ``mission.link.roster``; at load 20 one
stayed away past 3 s). Against a makespan of minutes, a dead robot's pots moving 10 s later
cost little; its aisles are freed sooner (``fleet.aisle_locks.LOCK_GRACE``)."""


class DispatchError(Exception):
    """Something that stops a fleet patrol from starting (a robot refused its part)."""


@dataclass
class Handover:
    """Pots of a robot that dropped out, given to another."""

    pots: list[str]
    from_robot: str
    to_robot: str
    why: str
    at_s: float
    """The giver's robot time since its patrol started, s."""

    def row(self) -> dict:
        return {"pots": self.pots, "from": self.from_robot, "to": self.to_robot, "why": self.why, "at_s": round(self.at_s, 1)}


@dataclass
class Member:
    """One robot as the dispatcher follows it."""

    name: str
    dock: Pose
    client: LinkClient
    assigned: list[str] = field(default_factory=list)
    received: list[str] = field(default_factory=list)
    waiting: list[str] = field(default_factory=list)
    """Pots handed to it while on patrol: its next patrol."""
    reports: list[dict] = field(default_factory=list)
    """Its ended patrols' reports, in order."""
    current: dict | None = None
    """The running patrol's report as last fetched."""
    on_patrol: bool = False
    out: str | None = None
    """Why it dropped out (``fleet_report.REASONS``), None while in."""
    handed_over: list[str] = field(default_factory=list)
    t0: float | None = None
    t_end: float | None = None
    estop_at: float | None = None
    """Its clock when its e-stop was last seen held (None: released)."""
    estop_alone: float = 0.0
    """Seconds of its clock its e-stop has been held while another robot could go on: a fleet
    e-stop counts nothing, nor its release, seen on one robot's telemetry a beat before another's
    (at load the fleet e-stop test's r2, stopped 30 s, was handed over at the resume: by all signs
    r1's release showed on its telemetry before r2's, and the whole stop counted)."""
    fetched_at: float = float("-inf")
    absent_since: float | None = None
    part: set[str] = field(default_factory=set)
    """The pots of its current (or last) patrol."""
    path: list[tuple[float, float]] = field(default_factory=list)

    def all_reports(self) -> list[dict]:
        """Its patrols' reports in order, the running one's last as fetched."""
        return self.reports + ([self.current] if self.current else [])

    def inspected(self) -> set[str]:
        return {p["id"] for r in self.all_reports() for p in r.get("pots", []) if p.get("status") == "inspected"}

    def run(self) -> RobotRun:
        """Its share for ``fleet.json``: its reports' pots together, its robot time from the
        first patrol's start to the last one's end (or its loss) on its own clock."""
        reports = self.all_reports()
        time_s = (self.t_end - self.t0) if self.t0 is not None and self.t_end is not None else \
            sum(float(r.get("sim_time_s", 0.0)) for r in reports)
        outcome = "lost" if self.out == "liveliness" else (reports[-1].get("outcome") if reports else None)
        merged = {"outcome": outcome, "sim_time_s": round(time_s, 3), "pots": [p for r in reports for p in r.get("pots", [])]}
        files = [f"{self.name}/{report_name(k)}" for k in range(len(reports))]
        return RobotRun(self.name, list(self.assigned), merged, list(self.received), list(self.handed_over), self.out,
                        np.asarray(self.path) if self.path else None, files)


class Dispatcher:
    def __init__(self, session: zenoh.Session, mission: Mission, docks: Mapping[str, Pose], grid: CostGrid,
                 occupancy: OccupancyMap | None, handover_after: float, *, clock: Callable[[], float] = time.monotonic,
                 say: Callable[[str], None] = lambda line: None, timeout: float = 10.0):
        self.session, self.mission, self.docks, self.grid, self.occupancy = session, mission, dict(docks), grid, occupancy
        self.handover_after, self.clock, self.say, self.timeout = handover_after, clock, say, timeout
        self.roster = Roster(session)
        self.locks = AisleLockServer(session, clock)
        self.members: dict[str, Member] = {}
        self.handovers: list[Handover] = []
        self.pots = {p.id: p for p in mission.pots}
        pots = np.array([(p.x, p.y, p.facing) for p in mission.pots])
        # each aisle's outline in the fleet's frame, numbered as fleet.assign's (the same map and pots)
        self.aisles = outlines(find_aisles(occupancy, pots)) if occupancy is not None else {}

    # --- the start ---------------------------------------------------------------------------
    def wait_for_robots(self, wanted: Sequence[str] | None, within: float) -> list[str]:
        """The robots up (all of ``wanted``, when given), waiting up to ``within`` s for them to
        appear; InputError naming who is missing, or that none is up."""
        end = self.clock() + within
        while True:
            up = self.roster.robots()
            if wanted is not None and set(wanted) <= set(up):
                return sorted(wanted)
            if self.clock() >= end:
                break
            time.sleep(POLL)
        if wanted is not None:
            missing = sorted(set(wanted) - set(up))
            raise InputError(f"--robots: {', '.join(missing)} not up on the router (up: {', '.join(up) or 'none'})")
        if not up:
            raise InputError("no robot is up on the router (start them: lupin fleet sim, or lupin serve --robot NAME)")
        return up

    def start(self, robots: Sequence[str]) -> None:
        """Split the mission between ``robots`` and send each its part."""
        for r in robots:
            if r not in self.docks:
                raise InputError(f"robot {r}: no dock known for it (the world's spawns name r1..r{len(self.docks)}; "
                                 "on a farm give fleet.docks in the config)")
            self.members[r] = Member(r, self.docks[r], LinkClient(None, r, clock=self.clock, timeout=self.timeout,
                                                                  session=self.session))
        a = assign(self.mission, self.grid, self.docks, up=list(robots), occupancy=self.occupancy)
        for r in robots:
            part = a.missions.get(r)
            self.say(f"{r}: {len(part.pots) if part else 0} pots")
            if part is not None:
                self._send(self.members[r], part)

    def _send(self, m: Member, part: Mission) -> None:
        data = part.model_dump(mode="json")
        data["pots"] = [p.model_dump(mode="json", exclude_none=True) for p in part.pots]
        aisles = {str(k): _in_dock_frame(poly, m.dock) for k, poly in self.aisles.items()}
        mine = {p.id for p in part.pots}  # the others, so that its person tracker knows them for pots
        others = np.array([[p.x, p.y] for p in self.mission.pots if p.id not in mine]).reshape(-1, 2)
        error = m.client.send("mission_start", mission=data, **({"aisles": aisles} if aisles else {}),
                              **({"others": _in_dock_frame(others, m.dock)} if len(others) else {}))
        if error is not None and " within " not in error:
            raise DispatchError(f"{m.name} refused its patrol: {error}")
        if error is not None:  # queued on a busy runtime (its first patrol compiles the planner's kernels): it comes
            self.say(f"{m.name}: {error}; following it")
        m.assigned += [p.id for p in part.pots if p.id not in m.assigned]
        m.part = {p.id for p in part.pots}
        m.on_patrol, m.current, m.fetched_at = True, None, float("-inf")
        if m.t0 is None:
            m.t0 = m.client.view().t

    # --- following ---------------------------------------------------------------------------
    def step(self) -> bool:
        """One look at every robot; True when the fleet patrol is over."""
        up = set(self.roster.robots())
        for m in self.members.values():
            if m.out is not None:
                continue
            if m.name not in up:
                m.absent_since = self.clock() if m.absent_since is None else m.absent_since
                if (m.on_patrol or m.waiting) and self.clock() - m.absent_since > LOST_AFTER:
                    self._drop(m, "liveliness")
                continue
            m.absent_since = None
            if m.on_patrol:
                self._follow(m)
            elif m.waiting:
                pots, m.waiting = m.waiting, []
                self._send_pots(m, pots)
        return not any(m.out is None and (m.on_patrol or m.waiting) for m in self.members.values())

    def _follow(self, m: Member) -> None:
        v = m.client.view()
        if v.connected:
            m.t_end = v.t
            p = compose(Pose2D(*m.dock), Pose2D(*v.pose))
            if not m.path or abs(m.path[-1][0] - p.x) + abs(m.path[-1][1] - p.y) > 0.05:
                m.path.append((p.x, p.y))
        seen = sum(p.status == "inspected" for p in v.pots) if v.mission_name == self.mission.name else 0
        if v.mission_state == "done" or seen > len(m.inspected()) or self.clock() - m.fetched_at > REPORT_EVERY:
            self._fetch(m)
            if m.current is not None and m.current.get("outcome") is not None:
                m.reports.append(m.current)
                m.current, m.on_patrol = None, False
                self.say(f"{m.name}: patrol {m.reports[-1]['outcome']}, {len(m.inspected())}/{len(m.assigned)} pots inspected")
                if m.reports[-1]["outcome"] == "battery_low" and set(m.assigned) - m.inspected():
                    self._drop(m, "battery_low")
                return
        if v.connected and v.estop_engaged:
            if m.estop_at is not None and self._takers(m):  # stopped while another robot could go on
                m.estop_alone += max(v.t - m.estop_at, 0.0)
            m.estop_at = v.t
            if m.estop_alone > self.handover_after:
                self._drop(m, "estop")
        else:
            m.estop_at, m.estop_alone = None, 0.0

    def _fetch(self, m: Member) -> None:
        m.fetched_at = self.clock()
        got, error = m.client.ask("report")
        if error is None and got is not None and got.get("mission") == self.mission.name and \
                {p["id"] for p in got.get("pots", [])} <= m.part:  # this patrol's, not the one before
            m.current = got

    def _takers(self, giver: Member) -> list[str]:
        """The robots that can take pots now: up, in, not stopped."""
        up = set(self.roster.robots())
        return sorted(m.name for m in self.members.values() if m is not giver and m.out is None and m.name in up
                      and not m.client.view().estop_engaged)

    # --- handing over ------------------------------------------------------------------------
    def _drop(self, m: Member, why: str) -> None:
        m.out = why
        if why != "liveliness" and m.on_patrol:
            m.client.send("mission_abort")
            deadline = self.clock() + self.timeout
            while self.clock() < deadline:  # its report, finished as aborted
                self._fetch(m)
                if m.current is not None and m.current.get("outcome") is not None:
                    break
                time.sleep(POLL)
            self.locks.free(m.name)  # its aisles, held while it stood stopped (a dead one's go with its token)
        if m.current is not None:
            m.reports.append(m.current)
            m.current = None
        m.on_patrol = False
        if m.client.view().connected:
            m.t_end = m.client.view().t
        done = m.inspected()
        left = [p for p in m.assigned if p not in done]  # those waiting for its next patrol too
        m.waiting = []
        m.handed_over = left
        takers = self._takers(m)
        self.say(f"{m.name}: out ({why}); {len(left)} pots to {', '.join(takers) or 'nobody'}")
        if not left or not takers:
            return
        a = assign(self._part(left), self.grid, self.docks, up=takers, occupancy=self.occupancy)
        since = (m.t_end - m.t0) if m.t_end is not None and m.t0 is not None else 0.0
        for r, part in a.missions.items():
            ids = [p.id for p in part.pots]
            taker = self.members[r]
            self.handovers.append(Handover(ids, m.name, r, why, since))
            taker.received += ids
            taker.assigned += [i for i in ids if i not in taker.assigned]  # its own to hand on, should it drop out too
            taker.waiting += ids
            if not taker.on_patrol:
                pots, taker.waiting = taker.waiting, []
                self._send_pots(taker, pots)

    def _part(self, ids: Sequence[str]) -> Mission:
        return self.mission.model_copy(update={"pots": [self.pots[i] for i in ids]})

    def _send_pots(self, m: Member, ids: list[str]) -> None:
        """A further patrol of ``ids`` for ``m`` (from its dock, in a short order)."""
        part = assign(self._part(ids), self.grid, self.docks, up=[m.name], occupancy=self.occupancy).missions[m.name]
        self.say(f"{m.name}: a further patrol of {len(ids)} pots")
        self._send(m, part)

    def run(self, deadline: float | None = None) -> bool:
        """Follow until the fleet patrol is over (True) or ``deadline`` on the clock passes (False)."""
        while not self.step():
            if deadline is not None and self.clock() > deadline:
                return False
            time.sleep(POLL)
        return True

    def runs(self) -> list[RobotRun]:
        return [m.run() for m in sorted(self.members.values(), key=lambda m: m.name)]

    def close(self) -> None:
        for m in self.members.values():
            m.client.close()
        self.locks.close()
        self.roster.close()


def _in_dock_frame(polygon: np.ndarray, dock: Pose) -> list[list[float]]:
    """A fleet-frame outline as the robot docked at ``dock`` maps it (its dock the origin)."""
    c, s = math.cos(dock[2]), math.sin(dock[2])
    d = polygon - np.asarray(dock[:2])
    return np.round(np.c_[c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], 3).tolist()


def report_name(k: int) -> str:
    """A robot's ``k``-th patrol's report in the fleet's directory: ``report.json`` for its
    first (spec/fleet.md), ``report-2.json`` ... for the further patrols handed to it."""
    return "report.json" if k == 0 else f"report-{k + 1}.json"


def write_results(out, d: Dispatcher) -> dict:
    """``out/<robot>/report.json`` (and further patrols'), ``out/fleet.json``, ``out/fleet.png``;
    the fleet summary."""
    for m in d.members.values():
        for k, report in enumerate(m.all_reports()):
            (out / m.name).mkdir(parents=True, exist_ok=True)
            write_atomic(out / m.name / report_name(k), (json.dumps(report, indent=2) + "\n").encode())
    pots = {p.id: (p.x, p.y) for p in d.mission.pots}
    return write_fleet_report(out, d.mission.name, pots, d.runs(), d.occupancy, [h.row() for h in d.handovers])
