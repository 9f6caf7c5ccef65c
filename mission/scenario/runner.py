"""Running a scenario: the patrol in the sim with its events, then every expectation checked.

Each expectation becomes one :class:`Check` with what was expected and what happened, so a
failure reads like ``estop.zero_duty_within_ticks: expected <= 1 tick after every press, got 2
(press at 40.0 s)``. The report, images and map of the run stay in the directory given.
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
from mission.scenario.judge import MotionLog, Press, estop_figures
from mission.scenario.scenario_file import Expect, PotsExpect, Scenario

ARM_TOLERANCE = 0.05
"""True joint error within which the arm counts as at a preset, rad (the servos' ~0.02 rad
dead-band plus settling)."""


@dataclass
class Check:
    name: str
    passed: bool
    expected: str
    actual: str

    def line(self) -> str:
        mark = "pass" if self.passed else "FAIL"
        return f"  {mark}  {self.name}: " + (self.actual if self.passed else f"expected {self.expected}, got {self.actual}")


@dataclass
class ScenarioResult:
    name: str
    path: str
    checks: list[Check]
    sim_time_s: float
    wall_time_s: float
    report: str
    presses: list[Press] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    def as_json(self) -> dict:
        return {
            "name": self.name, "file": self.path, "passed": self.passed,
            "sim_time_s": round(self.sim_time_s, 3), "wall_time_s": round(self.wall_time_s, 3), "report": self.report,
            "checks": [{"name": c.name, "passed": c.passed, "expected": c.expected, "actual": c.actual} for c in self.checks],
            "estop": [{"at": round(p.at, 3), "speed_mps": round(p.speed, 3), "ticks_to_zero": p.ticks_to_zero, "distance_after_m": round(p.distance_after, 4),
                       "still_after_release": p.still_after_release} for p in self.presses],
        }


@dataclass
class Ending:
    """What the judge reads at the end of a run, beside the report."""

    doc: dict
    stopped_at_limit: bool
    home_error: float
    arm_preset: str
    presses: list[Press]
    directory: Path


def run_scenario(scenario: Scenario, directory: Path, wall_now: Callable[[], float] = time.perf_counter) -> ScenarioResult:
    wall0 = wall_now()
    run = start_sim_patrol(scenario.world, scenario.mission, scenario.config, Path(directory) / "report.json", wall_now,
                           scenario.events)
    log = MotionLog(run.sim.sim).attach()
    doc = run_to_end(run, limit=scenario.expect.max_sim_time)
    ending = Ending(doc, doc.get("reason", "").startswith("time limit"), _home_error(run), _arm_preset(run),
                    estop_figures(log, scenario.events, run.report.t0, run.robot.scheduler.clock.now()), Path(directory))
    return ScenarioResult(scenario.name, str(scenario.path), expectations(scenario.expect, ending), doc["sim_time_s"],
                          wall_now() - wall0, str(Path(directory) / "report.json"), ending.presses)


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


# --- expectations -------------------------------------------------------------------------

def expectations(x: Expect, e: Ending) -> list[Check]:
    doc, checks = e.doc, []
    if x.outcome is not None:
        actual = doc["outcome"] + (f" ({doc['reason']})" if doc.get("reason") else "")
        checks.append(Check("outcome", doc["outcome"] == x.outcome, x.outcome, actual))
    ended = "still running at the limit" if e.stopped_at_limit else f"ended at {doc['sim_time_s']:.1f} s"
    checks.append(Check("max_sim_time", not e.stopped_at_limit or x.outcome == "aborted",
                        f"the run to end within {x.max_sim_time:g} s", ended))
    if x.pots is not None:
        checks += _pots(x.pots, doc)
    kinds = [(a["kind"], a["pot"]) for a in doc["anomalies"]]
    for want in x.anomalies:
        found = any(k == want.kind and (want.pot is None or p == want.pot) for k, p in kinds)
        where = f" at {want.pot}" if want.pot else ""
        checks.append(Check(f"anomalies: {want.kind}{where}", found, f"a {want.kind} anomaly{where}",
                            "found" if found else f"anomalies {_anomalies(kinds)}"))
    for kind in x.no_anomalies:
        at = [p for k, p in kinds if k == kind]
        checks.append(Check(f"no_anomalies: {kind}", not at, f"no {kind} anomaly", f"{kind} at {', '.join(at)}" if at else "none"))
    if x.home is not None:
        checks.append(Check("home", e.home_error <= x.home.within, f"within {x.home.within:g} m of home",
                            f"{e.home_error:.3f} m from home"))
    if x.arm is not None:
        checks.append(Check("arm", e.arm_preset == x.arm, f"the arm at {x.arm}", f"the arm at {e.arm_preset}"))
    if x.estop is not None:
        checks += _estop(x.estop.zero_duty_within_ticks, x.estop.still_until_resume, e.presses)
    for name in x.report_files:
        present = (e.directory / name).is_file()
        checks.append(Check(f"report_files: {name}", present, f"{name} beside the report", "present" if present else "missing"))
    return checks


def _anomalies(kinds: list[tuple[str, str]]) -> str:
    return "[" + ", ".join(f"{k} at {p}" for k, p in kinds) + "]" if kinds else "none"


def _pots(x: PotsExpect, doc: dict) -> list[Check]:
    status = {p["id"]: p["status"] for p in doc["pots"]}
    out = []
    for want in ("inspected", "failed", "skipped"):
        spec = getattr(x, want)
        if spec is None:
            continue
        have = [i for i, s in status.items() if s == want]
        if spec == "all":
            ok, expected = len(have) == len(status), f"all {len(status)} pots {want}"
        elif isinstance(spec, int):
            ok, expected = len(have) == spec, f"{spec} pots {want}"
        else:
            ok, expected = all(status.get(i) == want for i in spec), f"{', '.join(spec)} {want}"
        others = {s: [i for i, v in status.items() if v == s] for s in sorted(set(status.values()))}
        actual = "; ".join(f"{s}: {', '.join(ids)}" for s, ids in others.items())
        out.append(Check(f"pots.{want}", ok, expected, actual))
    return out


def _estop(within: int | None, still: bool | None, presses: list[Press]) -> list[Check]:
    out = []
    if not presses:
        return [Check("estop", False, "an e-stop press in the events", "no press scripted")]
    if within is not None:
        worst = [p for p in presses if p.ticks_to_zero is None or p.ticks_to_zero > within]
        shown = ", ".join(f"{p.ticks_to_zero} at {p.at:.1f} s" for p in presses)
        out.append(Check("estop.zero_duty_within_ticks", not worst,
                         f"<= {within} tick(s) after every press", f"ticks to zero duty: {shown}"))
    if still is not None:
        released = [p for p in presses if p.released is not None]
        moved = [p for p in released if not p.still_after_release]
        shown = ", ".join(f"{p.moved_after_release * 1000:.1f} mm after the release at {p.released:.1f} s" for p in released)
        ok = (not moved) == still and (bool(released) or not still)
        out.append(Check("estop.still_until_resume", ok,
                         "no wheel duty or motion between each release and its resume" if still else "motion after a release",
                         shown or "never released"))
    return out
