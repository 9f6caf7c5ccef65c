"""Running a scenario: the patrol in the sim with its events, then every expectation checked.

The judge watches from outside the stack (``mission.scenario.motion_log``) while the run plays,
then turns the log and the instants the events really fired into the e-stop figures
(``mission.scenario.judge``) and each event's effect (``mission.scenario.effects``), and checks
the expectations (``mission.scenario.checks``). The report, images and map of the run stay in
the directory given. A fleet scenario (``robots: N``) runs the fleet instead
(``fleet.scenario_runner``).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from arm.presets import ARM_JOINTS, PRESETS
from mission.jobs.patrol import PatrolRun, run_to_end
from mission.jobs.sim_patrol import start_sim_patrol
from mission.scenario.checks import Check, Ending, expectations
from mission.scenario.effects import EventEffect, event_effects
from mission.scenario.judge import Press, estop_figures
from mission.jobs.people_log import PeopleLog
from mission.scenario.motion_log import MotionLog
from mission.scenario.scenario_file import Scenario

ARM_TOLERANCE = 0.05
"""True joint error within which the arm counts as at a preset, rad (the servos' ~0.02 rad
dead-band plus settling)."""


@dataclass
class ScenarioResult:
    name: str
    path: str
    checks: list[Check]
    sim_time_s: float
    wall_time_s: float
    report: str
    presses: list[Press] = field(default_factory=list)
    events: list[EventEffect] = field(default_factory=list)
    t0: float = 0.0
    people: dict | None = None
    """Clearance and contacts with the walkers (worlds with walkers)."""
    fleet: dict | None = None
    """A fleet scenario's robots and ground-truth figures (``fleet.scenario_runner``)."""

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    def as_json(self) -> dict:
        return {
            "name": self.name, "file": self.path, "passed": self.passed,
            "sim_time_s": round(self.sim_time_s, 3), "wall_time_s": round(self.wall_time_s, 3), "report": self.report,
            "checks": [{"name": c.name, "passed": c.passed, "expected": c.expected, "actual": c.actual} for c in self.checks],
            "estop": [press_json(p, self.t0) for p in self.presses],
            "events": [v.as_json(self.t0) for v in self.events],
            **({"people": self.people} if self.people is not None else {}),
            **({"fleet": self.fleet} if self.fleet is not None else {}),
        }


def press_json(p: Press, t0: float) -> dict:
    """One press's e-stop figures, times from ``t0`` (the mission's start)."""
    return {"at": round(p.at - t0, 3), "speed_mps": round(p.speed, 3), "ticks_to_zero": p.ticks_to_zero,
            "distance_after_m": round(p.distance_after, 4), "still_after_release": p.still_after_release}


def run_scenario(scenario: Scenario, directory: Path, wall_now: Callable[[], float] = time.perf_counter) -> ScenarioResult:
    """One robot's scenario (a fleet's is ``fleet.scenario_runner.run_any``'s: ``fleet`` sits above
    ``mission``)."""
    if scenario.spec.robots is not None:
        raise ValueError(f"{scenario.name}: a fleet scenario (robots: {scenario.spec.robots}) runs with fleet.scenario_runner")
    wall0 = wall_now()
    run = start_sim_patrol(scenario.world, scenario.mission, scenario.config, Path(directory) / "report.json", wall_now,
                           scenario.events)
    log = MotionLog(run.sim.sim, run.robot.base, run.nav.localisation).attach()
    people = PeopleLog(run.sim.sim, scenario.config.arm.kinematics, driving=run.robot.base.driving).attach()
    doc = run_to_end(run, limit=scenario.expect.max_sim_time)
    end, t0, fired = run.robot.scheduler.clock.now(), run.report.t0, run.events.fired
    presses = estop_figures(log, scenario.events, fired, end)
    events = event_effects(log, scenario.events, fired, end, scenario.expect.effects)
    ending = Ending(doc, doc.get("reason", "").startswith("time limit"), _home_error(run), _arm_preset(run), presses,
                    events, t0, Path(directory), people)
    return ScenarioResult(scenario.name, str(scenario.path), expectations(scenario.expect, ending), doc["sim_time_s"],
                          wall_now() - wall0, str(Path(directory) / "report.json"), presses, events, t0,
                          people.as_json() if run.sim.sim.world.walkers else None)


def _home_error(run: PatrolRun) -> float:
    here = run.sim.to_map(run.sim.sim.truth())
    home = run.tree.mission.home
    return math.hypot(here.x - home.x, here.y - home.y)


def _arm_preset(run: PatrolRun) -> str:
    q = np.array([run.sim.sim.servos.joint_position(j) for j in ARM_JOINTS])
    for name, p in PRESETS.items():
        if np.all(np.abs(q - np.asarray(p)) <= ARM_TOLERANCE):
            return name
    return "none (" + ", ".join(f"{v:.2f}" for v in q) + " rad)"
