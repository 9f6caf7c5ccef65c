"""`lupin survey`: a greenhouse with no mission, explored from the dock and its pots found by
their tags; what it writes is the mission a patrol runs, and the map.

Three phases on the runtime's 10 Hz beat, after the patrol's start-up (the controllers healed,
the readiness cascade active, the arm in its travel pose, out of the front camera's view):

1. **Explore** (``nav.frontiers``): drive to the nearest frontier of the SLAM map, by path,
   until none is left; one the navigator cannot reach within ``goal_timeout`` is left out. A
   frontier seen into on the way is dropped for the next.
2. **Look** (``nav.viewpoints``): the map's pots, each looked at from every side the robot fits;
   the looks one way along a line of pots make a lane, and the robot takes a lane's looks in
   order, strafing from one to the next with its heading held, so the mecanum base moves down the
   aisle with its camera square to the plates and reads them as it goes; at each look a frame is
   taken standing. A look at a pot a tag has already placed is skipped (the drive to it dropped
   on the way). The next lane is the one that finds the most pots not yet found per metre of
   driving (to it, by path, and along it). The lanes down the aisles find the pots, so the lanes
   across the rows (the gaps between pots, where no plate faces) end up skipped.
3. **Home**: back to the dock.

All the while, every front frame's tag reads place pots (``mission.patrol.tag_sightings``);
``max_time`` of robot time ends the first two phases early. The mission has one pot per tag
read, at the fused position and facing, its id from the tag (``T017``), in the shortest order.
Ground truth never enters: the sim's world only builds the sim.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum
from typing import Callable

import numpy as np

from hw.odometry import Pose2D
from arm.presets import preset
from mission.patrol.mission_file import Home, Mission, MissionPot
from mission.patrol.tag_sightings import TagSightings
from mission.runtime.config import LupinConfig, with_overrides
from mission.runtime.heal import heal_controllers
from mission.runtime.navigation import final_map
from mission.runtime.robot import Robot
from nav.frontiers import nearest_frontier
from nav.navigator import Navigator, State
from nav.occupancy import OccupancyMap
from nav.path_lengths import lengths_from
from nav.viewpoints import Lane, Look, lanes, lattice_angle, looks, pot_blobs
from perception.camera_pipeline import camera_pipelines
from perception.config import PerceptionConfig
from perception.tag_reader import TagReader

TICK_RATE = 10.0
TRACE_RATE = 10.0
FRONTIER_CHECK = 1.0
"""Seconds between checks that the frontier being driven to is still one."""
LOOK_TOLERANCE = 0.1
"""Metres a lane's end (or a single look) must be reached to: a plate framed from farther off
its look can leave the frame."""


class Phase(str, Enum):
    STARTUP = "start-up"
    EXPLORE = "explore"
    LOOK = "look at pots"
    HOME = "home"
    DONE = "done"


def survey_perception(config: LupinConfig, perception: PerceptionConfig) -> PerceptionConfig:
    """The perception config with the front camera at the survey's rate and every tag of the
    family read (no mission says which plates exist yet)."""
    tag = perception.tag.model_copy(update={"whitelist": tuple(range(0, 587))})
    rates = perception.rates.model_copy(update={"front": config.survey.front_rate})
    return perception.model_copy(update={"tag": tag, "rates": rates})


@dataclass
class SurveyRun:
    robot: Robot
    nav: Navigator
    config: LupinConfig
    perception: PerceptionConfig
    close: Callable[[], None]
    phase: Phase = Phase.STARTUP
    reason: str = ""
    """Why the survey ended early, if it did."""
    path: list[tuple[float, float]] = field(default_factory=list)
    blocked: list[tuple[float, float]] = field(default_factory=list)
    pots: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    """The map's pots (``nav.viewpoints.pot_blobs``) when the looking began."""
    looks: list[Look] = field(default_factory=list)
    lanes: list[Lane] = field(default_factory=list)
    found: set[int] = field(default_factory=set)
    """Indices of the map's pots a tag has put in place."""
    looked: int = 0
    frontiers_driven: int = 0

    def __post_init__(self) -> None:
        clock = self.robot.scheduler.clock
        self.t0 = clock.now()
        self.cameras = camera_pipelines(self.robot.hal.cameras, clock, self.perception)
        self.reader = TagReader(self.perception.tag)
        cfg = self.config.patrol
        self.sightings = TagSightings(cfg.front_camera_mount, cfg.plate_offset)
        self._goal: tuple[str, Pose2D] | None = None
        self._arrived_at: float | None = None
        self._checked = self.t0
        self._last_frame: float | None = None
        self._sweep: list[Look] | None = None
        """What is left of the lane being swept: the goals still to drive to (None: dropped)."""
        self._lane: Lane | None = None

    # --- the run -----------------------------------------------------------------------------
    @property
    def now(self) -> float:
        return self.robot.scheduler.clock.now()

    @property
    def done(self) -> bool:
        return self.phase is Phase.DONE

    def step(self) -> None:
        self.robot.scheduler.step()

    def tick(self, now: float) -> None:
        self._watch()
        if self.phase in (Phase.EXPLORE, Phase.LOOK) and now - self.t0 >= self.config.survey.max_time:
            self._end_search(f"time limit: {self.config.survey.max_time:g} s of robot time")
        {Phase.STARTUP: self._startup, Phase.EXPLORE: self._explore, Phase.LOOK: self._look,
         Phase.HOME: self._home, Phase.DONE: lambda: None}[self.phase]()

    # --- phases ------------------------------------------------------------------------------
    def _startup(self) -> None:
        readiness = self.nav.readiness
        if self._goal is None:
            names = tuple(self.config.hw.controllers)
            heal_controllers(self.robot.controllers, names, self.robot.scheduler.clock, budget=0.0)
            self.robot.arm.preset(self.config.patrol.travel_pose)
            self._goal = ("start-up", Pose2D())
        if readiness.active and self.robot.arm.at(preset(self.config.patrol.travel_pose), tol=0.05):
            self._goal = None
            self.phase = Phase.EXPLORE
        elif readiness.overdue(self.now):
            self.reason = f"navigation {readiness.status(self.now)}"
            self.phase = Phase.DONE

    def _explore(self) -> None:
        if self.nav.active:
            if self.now - self._checked >= FRONTIER_CHECK:
                self._checked = self.now
                occupancy = self._map()
                target = self._goal[1]
                if occupancy is not None and not _near_unknown(occupancy, target.x, target.y):
                    self.nav.cancel(self.now, "frontier explored on the way")
            return
        if self._goal is not None and self.nav.state is State.FAILED:
            self.blocked.append((self._goal[1].x, self._goal[1].y))
        occupancy = self._map()
        here = self.nav.map_pose()
        frontier = None if occupancy is None else nearest_frontier(
            occupancy, self.nav.global_costmap.grid, (here.x, here.y), self.config.survey.frontier_min_cells, self.blocked)
        if frontier is None:
            self._start_looking(occupancy)
            return
        self._drive("frontier", Pose2D(frontier.x, frontier.y, math.atan2(frontier.y - here.y, frontier.x - here.x)))
        self.frontiers_driven += 1

    def _start_looking(self, occupancy: OccupancyMap | None) -> None:
        cfg = self.config.survey
        self._goal = None
        self.phase = Phase.LOOK
        if occupancy is None:
            return
        self.pots = pot_blobs(occupancy, self.config.patrol.pot_radius, cfg.pot_max_size)
        self.looks = looks(self.pots, self.nav.global_costmap.grid, cfg.standoff)
        self.lanes = lanes(self.looks, lattice_angle(self.pots))

    def _look(self) -> None:
        if self._lane is not None and self._sweep is not None and all(v.pot in self.found for v in self._lane.looks):
            self.nav.cancel(self.now, "every pot of the lane found")
            self._sweep = None
        if self.nav.active:
            return
        if self._sweep is not None and self.nav.state is State.SUCCEEDED and self._goal is not None \
                and self._goal[0] == "look" and not self._framed():
            return  # at a look: a frame taken standing there, read first
        if self._sweep:
            self._sweep_on()
            if self._sweep is not None:
                return
        if self._lane is not None:
            self.looked += len(self._lane.looks)
            self.lanes = [lane for lane in self.lanes if lane.looks not in (self._lane.looks, self._lane.looks[::-1])]
        self._lane = self._next_lane()
        if self._lane is None:
            self._end_search("")
            return
        self._sweep = list(self._lane.looks)
        self._sweep_on()

    def _sweep_on(self) -> None:
        """On to the lane's next look at a pot not yet found (a short strafe along the aisle,
        the heading held); at the end of the lane, on to the next lane."""
        while self._sweep and self._sweep[0].pot in self.found:
            self._sweep.pop(0)
        if not self._sweep:
            self._sweep = None
            return
        v = self._sweep.pop(0)
        self._drive("look", Pose2D(v.x, v.y, v.yaw), LOOK_TOLERANCE)

    def _framed(self) -> bool:
        """A front frame taken ``settle`` after arriving has been read."""
        if self._arrived_at is None:
            self._arrived_at = self.now
        if self.cameras["front"].fresh(self._arrived_at + self.config.patrol.settle) is None:
            return False
        self._watch()
        self._arrived_at = None
        return True

    def _next_lane(self) -> Lane | None:
        """The lane that finds the most pots not yet found per metre: to its nearer end by path,
        then along it (it is swept from that end)."""
        todo = [lane for lane in self.lanes if any(v.pot not in self.found for v in lane.looks)]
        if not todo:
            return None
        here = self.nav.map_pose()
        ends = np.array([[e.x, e.y] for lane in todo for e in (lane.start, lane.end)])
        reach = lengths_from(self.nav.global_costmap.grid, (here.x, here.y), ends).reshape(-1, 2)
        gain = np.array([len({v.pot for v in lane.looks} - self.found) for lane in todo], float)
        cost = reach.min(axis=1) + np.array([lane.length for lane in todo]) + 1.0
        k = int(np.argmax(np.where(np.isfinite(cost), gain / cost, -1.0)))
        lane = todo[k]
        return lane.reversed() if reach[k, 1] < reach[k, 0] else lane

    def _home(self) -> None:
        if not self.nav.active:
            if self._goal is not None and self.nav.state is not State.SUCCEEDED:
                self.reason = self.reason or f"not home: {self.nav.reason}"
            self.phase = Phase.DONE
            for task in ("survey", "survey.trace"):
                self.robot.scheduler.cancel(task)

    def _end_search(self, reason: str) -> None:
        self.reason = self.reason or reason
        self.nav.cancel(self.now, reason or "search over")
        self.phase = Phase.HOME
        self._drive("home", Pose2D(), timeout=math.inf)  # however far: the progress checker ends a stuck drive

    # --- pieces ------------------------------------------------------------------------------
    def _drive(self, label: str, goal: Pose2D, xy_tolerance: float | None = None, timeout: float | None = None) -> None:
        self._goal = (label, goal)
        self._checked = self.now
        self.nav.navigate_to(goal, self.now, timeout or self.config.survey.goal_timeout, xy_tolerance)

    def _map(self) -> OccupancyMap | None:
        return self.nav.localisation.occupancy  # a survey maps as it goes (``survey_config``)

    def _watch(self) -> None:
        """Every new front frame's tag reads place pots; pots of the map they land near are found."""
        frame = self.cameras["front"].request()
        if frame is None or frame.stamp == self._last_frame:
            return
        self._last_frame = frame.stamp
        used = self.sightings.add(self.reader.read(frame.image), self.nav.map_pose())
        cfg = self.config.survey
        for s in used:
            if s.distance <= cfg.found_read and len(self.pots):
                near = np.hypot(self.pots[:, 0] - s.x, self.pots[:, 1] - s.y) <= cfg.found_radius
                self.found.update(int(i) for i in np.flatnonzero(near))

    # --- what it found -----------------------------------------------------------------------
    def mission(self, name: str) -> Mission:
        """One pot per tag read, at its fused pose, in the shortest order, home at the dock."""
        pots = [MissionPot(id=f"T{e.tag:03d}", x=round(e.x, 4), y=round(e.y, 4), facing=round(e.facing, 4), tag=e.tag)
                for e in self.sightings.estimates()]
        return Mission(name=name, home=Home(), pots=pots, order="shortest")

    def summary(self, occupancy: OccupancyMap | None, distance: float, wall_s: float) -> dict:
        explored = 0.0 if occupancy is None else float((occupancy.occupancy >= 0).sum()) * occupancy.resolution ** 2
        return {"pots_found": len(self.sightings.by_tag), "map_pots": int(len(self.pots)),
                "map_pots_found": len(self.found), "looks": len(self.looks), "looked": self.looked,
                "lanes_left": len(self.lanes),
                "frontiers": self.frontiers_driven, "explored_m2": round(explored, 1),
                "robot_time_s": round(self.now - self.t0, 1), "distance_m": round(distance, 2),
                "wall_time_s": round(wall_s, 1), "ended": self.reason or "complete"}

    def final_map(self) -> OccupancyMap | None:
        return final_map(self.nav, self.robot.scheduler)


def _near_unknown(occupancy: OccupancyMap, x: float, y: float, radius: float = 0.3) -> bool:
    """Is ground never seen within ``radius`` of the point (is it still a frontier)?"""
    geo = occupancy.geometry
    ix, iy = (int(v) for v in geo.cell_of(x, y))
    r = int(math.ceil(radius / geo.resolution))
    window = occupancy.occupancy[max(iy - r, 0):iy + r + 1, max(ix - r, 0):ix + r + 1]
    return window.size == 0 or bool((window < 0).any())


def start_survey(robot: Robot, nav: Navigator, config: LupinConfig, perception: PerceptionConfig,
                 close: Callable[[], None]) -> SurveyRun:
    """Schedule the survey on a running robot with navigation (SLAM mapping from the dock)."""
    run = SurveyRun(robot, nav, config, survey_perception(config, perception), close)

    def trace(now: float) -> None:
        pose = nav.map_pose()
        run.path.append((pose.x, pose.y))

    robot.scheduler.every("survey.trace", TRACE_RATE, trace)
    robot.scheduler.every("survey", TICK_RATE, run.tick)
    return run


def run_to_end(run: SurveyRun, on_step: Callable[[SurveyRun], None] = lambda r: None) -> SurveyRun:
    """Step until the survey is done (Ctrl-C: it ends where it is); the run is not closed."""
    try:
        while not run.done:
            run.step()
            on_step(run)
    except KeyboardInterrupt:
        run.nav.cancel(run.now, "interrupted")
        run.reason = "interrupted"
        run.phase = Phase.DONE
    return run


def survey_config(config: LupinConfig) -> LupinConfig:
    """A survey maps as it goes: SLAM, whatever the config's localisation."""
    return with_overrides(config, {"nav": {"slam": True}})


def start_hw_survey(config: LupinConfig) -> SurveyRun:
    """The survey on the robot's devices (a missing one is a clear error before anything moves)."""
    from mission.runtime.hw_runtime import start_hw_runtime

    config = survey_config(config)
    rt = start_hw_runtime(config)
    return start_survey(rt.robot, rt.nav, config, config.perception, rt.close)


def write_survey(run: SurveyRun, mission_path, map_path, report_path, name: str, wall_s: float) -> dict:
    """The mission, the map, the survey's report (its summary and every pot with its sightings)
    and a picture of what it found (``survey.png`` beside the report)."""
    import json
    from pathlib import Path

    from hw.atomic_file import write_atomic, write_png
    from mission.patrol.mission_file import dump_mission
    from mission.patrol.run_picture import PotMark, draw_run
    from nav.map_io import save_map

    occupancy = run.final_map()
    mission = run.mission(name)
    summary = run.summary(occupancy, run.robot.base.odometry.distance, wall_s)
    write_atomic(mission_path, dump_mission(mission).encode())
    if occupancy is not None:
        save_map(occupancy.cropped(), map_path)
    pots = [{"id": p.id, "tag": p.tag, "x": p.x, "y": p.y, "facing": p.facing,
             "sightings": run.sightings.estimate(p.tag).sightings,
             "nearest_read_m": round(run.sightings.estimate(p.tag).nearest, 3)} for p in mission.pots]
    doc = {"mission": str(mission_path), "map": str(map_path), **summary, "pots": pots}
    write_atomic(report_path, json.dumps(doc, indent=2).encode())
    marks = [PotMark(p.id, p.x, p.y, "inspected", False, f"{p.id} tag {p.tag}", None) for p in mission.pots]
    write_png(Path(report_path).parent / "survey.png",
              draw_run(occupancy, np.array(run.path, dtype=float).reshape(-1, 2), marks, (0.0, 0.0)))
    return doc
