"""Running a fleet scenario (``robots: N``): the real fleet patrol in one sim, its events, its judge.

Everything is the fleet's own: ``lupin fleet sim``'s robots (``mission.jobs.fleet_sim``: one
MuJoCo world, a runtime per robot in lock-step, each link joined to the router under its name),
a router on loopback (plain TCP: one machine, nothing to authenticate), and the dispatcher
(``fleet.fleet_patrol``) splitting the mission and following the robots through the router, as
``lupin fleet patrol`` does. The runtimes step on a thread of their own; the dispatcher runs on
the caller's.

Each robot's events are played on its own runtime (``mission.jobs.events``, as for one robot),
``at`` counted from the start of that robot's first patrol (when the dispatcher's part reaches
it; from the next control beat, ``on_beat``). The judge watches from outside: a motion log per
robot (``mission.scenario.motion_log``: its duties and true pose, for its e-stop figures and
event effects) and the fleet watch on the shared scene (``fleet.scenario_judge``:
contacts, aisles, true paths).

``max_sim_time`` counts from the first patrol's start: past it every patrol still running is
aborted (on the runtimes' thread, as an operator's abort), so the dispatcher ends too; ``GRACE``
later the runtimes close.

A fleet run is a function of its seed only as far as the dispatcher's wall-clock timing lets it:
the instant each robot's part reaches it is the link's, so two runs of a scenario may differ in
detail (not in what a scenario with margins judges).
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from fleet.fleet_map import plan_of_world
from fleet.fleet_patrol import Inputs, fleet_patrol, world_docks
from fleet.router import open_router
from fleet.scenario_judge import FleetWatch, fleet_checks, robot_checks, world_aisles
from mission.jobs.events import EventPlayer
from mission.jobs.fleet_sim import FleetSim, start_fleet_sim
from mission.jobs.serve import Service
from mission.link.session import free_endpoint
from mission.runtime.config import with_overrides
from mission.scenario.checks import Check
from mission.scenario.effects import event_effects
from mission.scenario.fleet_file import robot_names
from mission.scenario.judge import estop_figures
from mission.scenario.motion_log import MotionLog
from mission.scenario.runner import ScenarioResult, press_json, run_scenario
from mission.scenario.scenario_file import Scenario

WALL_LIMIT = 3600.0
"""Wall seconds the dispatcher follows the fleet at most: a guard for a runtime that hangs (the
scenario's own limit, ``max_sim_time``, is sim time and ends every patrol first)."""
GRACE = 60.0
"""s of sim time past ``max_sim_time`` after which the runtimes stop and close: a dispatcher still
following then (a part it thinks was queued, a report it never got) sees every robot's
liveliness go and ends, so a scenario that went wrong fails instead of hanging."""
COMMAND_TIMEOUT = 8.0
"""s a robot's link waits for its runtime to take a command: a first patrol starts slowly (the
planner's kernels compile), as in the fleet's tests."""


@dataclass
class RobotPlay:
    """One robot of the fleet as the scenario plays and watches it."""

    name: str
    events: list
    log: MotionLog
    player: EventPlayer | None = None
    t0: float | None = None
    """Its first patrol's start (runtime time), on the control beat at or after it: the zero of its
    events."""

    def on_run(self, service: Service, faults) -> Callable:
        """The service's listener: at its first patrol, its events are scheduled from that start."""

        def started(run) -> None:
            if run is None or self.player is not None:
                return
            self.t0 = on_beat(run.report.t0, service.robot.config.hw.base.control_rate)
            self.player = EventPlayer(service.robot, service.nav, run.tree.holds, faults)
            self.player.schedule(list(self.events), self.t0)

        return started

    @property
    def fired(self) -> dict[int, float]:
        return self.player.fired if self.player is not None else {}


def on_beat(t: float, rate: float) -> float:
    """The first control beat (every ``1 / rate`` s of the runtime clock) at or after ``t``. One
    robot's patrol starts on a beat, so its events (``at`` a multiple of the beat, or waiting
    for a beat with ``when_moving``) fire with the base's tick, before the wheels' next one; a
    fleet robot's starts when the dispatcher's part reaches it, off the beat, and its events are
    counted from the next beat so they play as one robot's do."""
    period = round(1e9 / rate)
    return -(-round(t * 1e9) // period) * period / 1e9


@dataclass
class Stepping:
    """The runtimes' thread: lock-step until stopped, every patrol aborted past the limit."""

    fleet: FleetSim
    plays: dict[str, RobotPlay]
    limit: float
    stop: threading.Event = field(default_factory=threading.Event)
    at_limit: bool = False
    error: BaseException | None = None

    def run(self) -> None:
        try:
            while not self.stop.is_set():
                self.fleet.step()
                starts = [p.t0 for p in self.plays.values() if p.t0 is not None]
                late = self.fleet.scene.engine.time - (min(starts, default=0.0) + self.limit)
                if late > GRACE:  # a dispatcher that never saw the end: the robots go, it hands over to nobody
                    break
                if late > 0:
                    for service in self.fleet.services.values():
                        if service.run is not None:
                            self.at_limit = True
                            service.mission_abort()
        except BaseException as exc:  # the caller re-raises it once the dispatcher is done
            self.error = exc
        finally:
            self.fleet.close()


def run_fleet_scenario(scenario: Scenario, directory: Path, wall_now: Callable[[], float] = time.perf_counter):
    """The fleet patrol of ``scenario`` played and judged; a ``ScenarioResult`` with ``fleet``."""
    wall0, directory = wall_now(), Path(directory)
    names, world = robot_names(scenario.spec.robots), scenario.world
    config = with_overrides(scenario.config, {"link": {"command_timeout": COMMAND_TIMEOUT}})
    endpoint = free_endpoint("tcp")
    router = open_router(endpoint, None, None)
    try:
        fleet = start_fleet_sim(world, config, names, directory / "runs", wall_now)
        fleet.join(endpoint, lambda name: None, None)
        plays = {}
        for name, service in fleet.services.items():
            sim = fleet.scene.robots[name]
            plays[name] = RobotPlay(name, scenario.robot_events[name],
                                    MotionLog(sim, service.robot.base, service.nav.localisation).attach())
            service.on_run.append(plays[name].on_run(service, sim.faults))
        watch = FleetWatch(fleet.scene, world_aisles(world)).attach(fleet.services[names[0]].robot.scheduler)
        stepping = Stepping(fleet, plays, scenario.expect.max_sim_time)
        thread = threading.Thread(target=stepping.run, name="fleet scenario", daemon=True)
        thread.start()
        said: list[str] = []
        try:
            first = world.spawn_poses[0]
            inputs = Inputs(scenario.mission, world_docks(world),
                            plan_of_world(world, (first.x, first.y, first.yaw), config.nav.costmap.resolution),
                            f"the plan of world {world.name!r}")
            summary = fleet_patrol(inputs, endpoint, None, names, directory / "fleet", config, said.append, WALL_LIMIT)
            end = max(s.now for s in fleet.services.values())
        finally:
            stepping.stop.set()
            thread.join(120)
        if stepping.error is not None:
            raise stepping.error
    finally:
        router.close()
    t0 = min((p.t0 for p in plays.values() if p.t0 is not None), default=0.0)
    checks, robots, stops = [], {}, {}
    for name, p in plays.items():
        presses = estop_figures(p.log, p.events, p.fired, end)
        effects = event_effects(p.log, p.events, p.fired, end, scenario.expect.effects)
        stops[name] = [(q.at, q.released if q.released is not None else end) for q in presses]
        robots[name] = {"summary": summary["robots"].get(name, {}), "t0": p.t0 if p.t0 is not None else t0,
                        "presses": presses, "events": effects}
    checks += robot_checks(scenario.expect, robots, stepping.at_limit)
    if scenario.expect.fleet is not None:
        checks += fleet_checks(scenario.expect.fleet, watch, summary, stops, t0)
    result = ScenarioResult(scenario.name, str(scenario.path), checks, end - t0, wall_now() - wall0,
                            str(directory / "fleet" / "fleet.json"), t0=t0)
    result.fleet = fleet_json(summary, robots, watch, t0, said)
    return result


def fleet_json(summary: dict, robots: dict, watch: FleetWatch, t0: float, said: list[str]) -> dict:
    """What ``--json`` adds for a fleet: per robot its share, presses and events (times from its
    own first patrol's start), and the fleet's ground-truth figures (times from the first start)."""
    per = {}
    for name, r in robots.items():
        s = r["summary"]
        per[name] = {"outcome": s.get("outcome"), "assigned": s.get("assigned", []), "done": s.get("done", []),
                     "handed_over": s.get("handed_over", []), "handover_reason": s.get("handover_reason"),
                     "robot_time_s": s.get("robot_time_s"), "start_s": round(r["t0"] - t0, 3),
                     "estop": [press_json(p, r["t0"]) for p in r["presses"]],
                     "events": [v.as_json(r["t0"]) for v in r["events"]]}
    return {"robots": per, "makespan_s": summary["makespan_s"], "pots": summary["pots"],
            "handovers": summary["handovers"], "robot_contacts": [
                {"at_s": round(t - t0, 2), "robots": [a, b]} for t, a, b in watch.contacts],
            "head_on_in_aisle": sum(m.head_on for m in watch.meetings),
            "meetings_in_aisle": [m.as_json(t0) for m in watch.meetings], "dispatcher": said}


def run_any(scenario: Scenario, directory: Path, wall_now: Callable[[], float] = time.perf_counter) -> ScenarioResult:
    """Any scenario file: a fleet's here, one robot's by ``mission.scenario.runner``."""
    if scenario.spec.robots is not None:
        return run_fleet_scenario(scenario, directory, wall_now)
    return run_scenario(scenario, directory, wall_now)
