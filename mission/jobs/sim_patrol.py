"""`lupin patrol` on the simulated greenhouse: the sim's cameras as the perception config, the
world's climate, ground truth for judging each pot, and an events file played into the run.

Kept apart from :mod:`mission.jobs.patrol` so that the patrol on the robot never imports the
simulator.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from hw.odometry import Pose2D
from mission.jobs.events import EventPlayer
from mission.jobs.navigate import NavigateRun, start_navigate
from mission.history.store import History
from mission.jobs.patrol import PatrolRun, start_patrol
from mission.patrol.climate import TableClimate
from mission.patrol.mission_file import Mission
from mission.patrol.report import pose_error
from mission.runtime.config import LupinConfig
from perception.config import CameraModelConfig, PerceptionConfig
from sim.world import World


def sim_perception(config: LupinConfig) -> PerceptionConfig:
    """Perception with the sim cameras' intrinsics (their size and field of view): in the sim
    the camera *is* its model, so the tag reader's K comes from there, not from a copy."""
    cam = config.sim.camera
    front = CameraModelConfig(width=cam.width, height=cam.height, fovy_deg=cam.front_fovy_deg)
    wrist = CameraModelConfig(width=cam.width, height=cam.height, fovy_deg=cam.wrist_fovy_deg)
    p = config.perception
    return p.model_copy(update={"tag": p.tag.model_copy(update={"camera": front}), "wrist_camera": wrist})


def start_sim_patrol(world: World, mission: Mission, config: LupinConfig, report_path: Path,
                     wall_now: Callable[[], float], events: list = (), sim_run: NavigateRun | None = None,
                     history: History | None = None) -> PatrolRun:
    """The patrol on the simulated greenhouse: the world's climate, truth for judging, and the
    events file's actions (``mission.jobs.events``) on the runtime clock from the start; on the
    running sim ``sim_run`` when given (a survey's, patrolling what it found); recorded in
    ``history`` when given, under the world's name."""
    sim_run = sim_run or start_navigate(world, config)

    def truth_error(goal: Pose2D) -> dict[str, float]:
        return pose_error(sim_run.to_map(sim_run.sim.truth()), goal)

    def play(run: PatrolRun) -> None:
        run.sim = sim_run
        run.events = EventPlayer(run.robot, run.nav, run.tree.holds, sim_run.sim.faults, crash=run.crash)
        if history is not None:
            run.events.history_down = lambda until: history.outage_until(until, run.robot.scheduler.clock.now)
        run.events.schedule(list(events), run.report.t0)

    return start_patrol(sim_run.robot, sim_run.nav, mission, config, sim_perception(config), report_path, wall_now,
                        sim_run.close, TableClimate(world.climate_readings()), truth_error, play,
                        history=history, world=world.name)
