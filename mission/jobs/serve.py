"""`lupin serve`: the robot runtime as a long-running service that operators command.

The robot's services and navigation run on the scheduler forever (the sim paced to the wall
clock by default, the robot on it by nature). A patrol starts and ends on command
(``mission_start`` / ``mission_abort``); when one ends, its report is finished in its own
directory under ``runs`` and the robot stays up, ready for the next. Everything an operator can
ask for is a method here, called on the runtime's own thread (``mission.link.server`` queues the
link's commands onto the scheduler), so nothing here needs a lock.
"""
from __future__ import annotations

import logging
import threading
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
from sqlalchemy.exc import SQLAlchemyError

from arm.calibration import Calibration, CalibrationError
from arm.controller import ArmUnavailable
from arm.limits import GRIPPER_CLOSED_DEG, GRIPPER_OPEN_DEG
from arm.presets import UnknownPreset
from hw.errors import InputError
from hw.interfaces import Twist
from hw.odometry import Pose2D
from mission.history.answers import BadQuery, answer
from mission.history.recorder import PatrolRecorder
from mission.history.store import History, reason
from mission.jobs.patrol import PatrolRun, start_patrol
from mission.link.aisle_client import AisleLockClient
from mission.link.commands import CommandRefused
from mission.link.wire import dumps
from mission.patrol.aisle_gate import AisleGate
from mission.patrol.aisle_outlines import AisleOutlines
from mission.patrol.climate import ClimateSource, NoClimate, TableClimate
from mission.patrol.mission_file import Mission, parse_mission
from mission.patrol.report import pose_error
from mission.runtime.config import LupinConfig
from mission.runtime.heal import heal_controllers
from mission.runtime.heap import release_freed_memory
from mission.runtime.navigation import attach_navigation, clear_map
from mission.runtime.hw_runtime import start_hw_runtime
from mission.runtime.robot import Robot
from nav.frames import compose, inverse
from nav.navigator import Navigator
from perception.camera_pipeline import CameraPipeline, camera_pipelines
from perception.config import PerceptionConfig

log = logging.getLogger("lupin")

MANUAL = "manual"


@dataclass
class Service:
    robot: Robot
    nav: Navigator
    config: LupinConfig
    perception: PerceptionConfig
    runs: Path
    """Each patrol's report goes to ``runs/<mission>-<k>/``."""
    wall_now: Callable[[], float]
    default_mission: Callable[[], Mission]
    climate: ClimateSource = field(default_factory=NoClimate)
    truth_error: Callable[[Pose2D], dict[str, float]] | None = None
    close_backend: Callable[[], None] = lambda: None
    run: PatrolRun | None = None
    outcome: str = ""
    """The last patrol's outcome ('' before any)."""
    cameras: dict[str, CameraPipeline] = field(default_factory=dict)
    on_run: list[Callable[[PatrolRun | None], None]] = field(default_factory=list)
    """Told of every patrol that starts, and None when it ends (the Foxglove channels follow)."""
    history: History | None = None
    """Where every patrol it runs is recorded (``mission.history``); None: nowhere."""
    world: str | None = None
    """The sim world's name, for the history; None on the robot."""
    report_path: Path | None = None
    """The current or last patrol's report.json (the ``report`` command reads it)."""
    aisle_client: AisleLockClient | None = None
    """Its way to the fleet's aisle locks, while its link is joined to a router (None: alone)."""
    _calibration: Calibration | None = None
    _writing: list[PatrolRecorder] = field(default_factory=list)
    _count: int = 0

    def __post_init__(self) -> None:
        self.cameras = camera_pipelines(self.robot.hal.cameras, self.robot.scheduler.clock, self.perception)

    @property
    def now(self) -> float:
        return self.robot.scheduler.clock.now()

    def step(self) -> None:
        """One scheduler step; a patrol that has just ended is finished (report, map, picture)."""
        self.robot.scheduler.step()
        if self.run is not None and self.run.done:
            self._end(self.run.outcome())

    def _end(self, outcome: str, reason: str = "") -> None:
        run, self.run = self.run, None
        self.outcome = run.finish(outcome, reason)["outcome"]
        if run.history is not None:  # its writer finishes on its own thread; close waits for it
            self._writing = [r for r in self._writing if r.pending] + [run.history]
        for listener in self.on_run:
            listener(None)
        log.info("patrol %s: %s (report %s)", run.tree.mission.name, self.outcome, run.report.path)
        release_freed_memory()  # a service runs patrols all season: it must not grow with each

    def close(self) -> None:
        if self.run is not None:
            self.run.abort()
            self._end("aborted", "the service was stopped")
        self.robot.close()
        self.close_backend()
        for recorder in self._writing:
            recorder.wait()
        if self.history is not None:
            self.history.close()

    # --- what an operator can do (mission.link.view.COMMANDS) --------------------------------
    def estop(self, engaged: bool) -> None:
        self.robot.estop.set_soft(engaged)

    def resume(self) -> None:
        if self.robot.estop.engaged():
            raise CommandRefused("resume refused: the e-stop is still engaged (release it first)")
        if self.run is not None:
            refused = self.run.tree.holds.resume()
            if refused:
                raise CommandRefused(refused)

    def pause(self) -> None:
        if self.run is None:
            raise CommandRefused("pause: no mission is running")
        self.run.tree.holds.pause()

    def mission_start(self, mission: dict | None = None, aisles: dict[str, list] | None = None,
                      others: list[list[float]] | None = None) -> None:
        if self.run is not None:
            raise CommandRefused(f"mission_start: {self.run.tree.mission.name!r} is still running (abort it first)")
        try:
            m = self.default_mission() if mission is None else parse_mission(mission, "mission")
        except InputError as exc:
            raise CommandRefused(f"mission_start: {exc}") from None
        for recorder in self._writing:  # the last patrol's rows are in before this one compares with them
            recorder.wait(2.0, retry=False)
        self._count += 1
        report = self.report_path = self.runs / f"{m.name}-{self._count}" / "report.json"
        gate = None
        if aisles and self.aisle_client is not None:  # a fleet's patrol: the aisles asked for on the way
            gate = AisleGate(self.aisle_client, AisleOutlines({int(k): np.asarray(v, float) for k, v in aisles.items()}))
        self.run = start_patrol(self.robot, self.nav, m, self.config, self.perception, report, self.wall_now,
                                lambda: None, self.climate, self.truth_error, history=self.history, world=self.world,
                                gate=gate, others=[(float(x), float(y)) for x, y in others or ()])
        for listener in self.on_run:
            listener(self.run)
        log.info("patrol %s started (%d pots)", m.name, len(m.pots))

    def mission_abort(self) -> None:
        if self.run is None:
            raise CommandRefused("mission_abort: no mission is running")
        self.run.abort()
        self._end("aborted", "aborted by the operator")

    def teleop(self, vx: float, vy: float, wz: float, source: str = MANUAL) -> None:
        self.robot.mux.publish(source, Twist(vx, vy, wz), self.now)

    def arm_preset(self, name: str) -> None:
        try:
            self.robot.arm.preset(name)
        except (UnknownPreset, ArmUnavailable) as exc:
            raise CommandRefused(f"arm_preset: {exc}") from None

    def gripper(self, action: str, deg: float | None = None) -> None:
        if action == "angle" and deg is None:
            raise CommandRefused("gripper: action 'angle' needs deg (-30 open .. +30 closed)")
        try:
            self.robot.arm.grip({"open": GRIPPER_OPEN_DEG, "close": GRIPPER_CLOSED_DEG}.get(action, deg))
        except ArmUnavailable as exc:
            raise CommandRefused(f"gripper: {exc}") from None

    def clear_map(self) -> None:
        try:
            clear_map(self.nav, self.now)
        except InputError as exc:
            raise CommandRefused(str(exc)) from None

    def heal(self) -> None:
        names = tuple(self.config.hw.controllers)
        healed = heal_controllers(self.robot.controllers, names, self.robot.scheduler.clock, budget=0.0)
        if not healed.healed:
            raise CommandRefused(f"heal: {healed.message}")

    def arm_calibrate(self, action: str) -> bytes:
        """The arm's zero-offset calibration (``arm.calibration``, the seed's start / commit /
        cancel / status) as JSON. The first call builds it on the robot's servo bus (the sim's
        refuses: hardware only) and gives it the arm's beat, which samples while it commits."""
        if self._calibration is None:
            try:
                self._calibration = Calibration(self.robot.hal.servos, self.config.hw.servos, self.config.arm.calibration,
                                                arm=self.robot.arm, log=log)
            except CalibrationError as exc:
                raise CommandRefused(f"arm_calibrate: {exc}") from None
            self.robot.scheduler.every("arm.calibration", self.config.arm.reassert.rate, self._calibration.tick)
        cal = self._calibration
        try:
            status = {"start": cal.start, "commit": lambda: cal.commit(self.now), "cancel": cal.cancel,
                      "status": cal.status}[action]()
        except CalibrationError as exc:
            raise CommandRefused(f"arm_calibrate {action}: {exc}") from None
        return dumps({"phase": status.phase.value, "joints": list(status.joints), "note": status.note,
                      "outcomes": [asdict(o) for o in status.outcomes]})

    def history_query(self, query: str, **args) -> bytes:
        """A question to the patrol history (``mission.history.answers``) as JSON. Called on the
        link's thread, not the runtime's: it reads the database only (its own connections)."""
        if self.history is None:
            raise CommandRefused("history: this robot records no patrol history (--history none)")
        try:
            return dumps(answer(self.history, query, **args))
        except BadQuery as exc:
            raise CommandRefused(str(exc)) from None
        except SQLAlchemyError as exc:
            raise CommandRefused(f"history: {self.history.shown}: {reason(exc)}") from None

    def report(self) -> bytes:
        """The current or last patrol's report.json as written so far (a fleet's dispatcher
        keeps each robot's report, spec/fleet.md, without reaching into the robot's disk)."""
        if self.report_path is None:
            raise CommandRefused("report: no patrol has started yet")
        try:
            return self.report_path.read_bytes()
        except OSError as exc:
            raise CommandRefused(f"report: {self.report_path}: {exc.strerror}") from None

    def snapshot(self, camera: str) -> bytes:
        frame = self.cameras[camera].request()
        if frame is None:
            raise CommandRefused(f"snapshot: the {camera} camera gave no frame")
        return frame.jpeg


def run_service(service: Service, stop: threading.Event, on_close: Callable[[], None] = lambda: None) -> None:
    """Step ``service`` until ``stop`` is set, then close it on this same thread (the sim's
    renderers belong to the thread that made them). ``on_close`` runs first (the link)."""
    try:
        while not stop.is_set():
            service.step()
    finally:
        on_close()
        service.close()


def start_hw_service(config: LupinConfig, runs: Path, wall_now: Callable[[], float],
                     history: History | None = None, monitor_off: bool = False, **boundaries) -> Service:
    """The service on the robot's devices (a missing one is a clear error before anything
    moves). There is no world to patrol by default: ``mission_start`` needs a mission.
    ``monitor_off``: ``--no-collision-monitor``; ``boundaries``: see ``start_hw_runtime``."""
    rt = start_hw_runtime(config, monitor_off, **boundaries)

    def no_default() -> Mission:
        raise CommandRefused("mission_start: the robot has no built-in mission; send one (spec/mission.md)")

    return Service(rt.robot, rt.nav, config, config.perception, Path(runs), wall_now, no_default,
                   close_backend=rt.backend.close, history=history)
