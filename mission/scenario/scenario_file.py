"""Scenario files (contract: spec/scenario.md): one simulated patrol, its events, its outcome.

A user pins down behaviour without writing Python: a world, a mission, an events list
(spec/events.md) and the expectations the run must meet. Read like the other user files
(``hw.input_file``): unknown keys rejected, every problem one line naming the file, the entry
and the field; the world, mission and events it names are read and checked too, and the config
overrides validated, all before anything runs (exit 2)::

    estop.yaml: expect: field 'pots.inspected': must be all, a number or a list of pot ids (got 'most')
    estop.yaml: events[1] (do estop): field 'engaged': missing required key

Paths in a scenario are relative to the scenario file.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, Optional, Union

from pydantic import Field, ValidationError, field_validator

from arm.presets import PRESETS
from hw.errors import InputError
from hw.input_file import StrictEntry, error_lines, kind_of, read_yaml
from mission.patrol.events_file import parse_events
from mission.patrol.mission_file import Mission, load_mission, mission_from_world
from mission.runtime.config import LupinConfig, with_overrides, with_seed
from mission.scenario.fleet_file import addressed, by_robot, check_fleet_file
from sim.world import World, load_default_world, load_world

OUTCOMES = ("completed", "aborted", "battery_low", "failed")

PotSet = Union[Literal["all"], int, list[str]]
"""``all``, how many, or which pot ids."""


def pot_set(v: Any) -> Any:
    ok = v is None or v == "all" or (isinstance(v, int) and not isinstance(v, bool) and v >= 0) or (
        isinstance(v, list) and all(isinstance(i, str) for i in v))
    if not ok:
        raise ValueError(f"must be all, a number or a list of pot ids (got {kind_of(v)})")
    return v


class PotsExpect(StrictEntry):
    inspected: Optional[PotSet] = None
    failed: Optional[PotSet] = None
    skipped: Optional[PotSet] = None

    @field_validator("inspected", "failed", "skipped", mode="before")
    @classmethod
    def _pot_set(cls, v: Any) -> Any:
        return pot_set(v)


class AnomalyExpect(StrictEntry):
    kind: str
    pot: Optional[str] = None
    """The pot it must be recorded at (any pot when left out)."""


class HomeExpect(StrictEntry):
    within: float = Field(gt=0)
    """Final ground-truth distance to the mission's home, m."""


class EStopExpect(StrictEntry):
    zero_duty_within_ticks: Optional[int] = Field(None, ge=1)
    """After every press, all four wheel duties are zero within this many control ticks."""
    still_until_resume: Optional[bool] = None
    """No wheel duty and no motion between each release and the operator's resume."""
    min_speed_at_press: Optional[float] = Field(None, gt=0)
    """Every press found the base driving at least this fast (m/s, ground truth over the control
    tick up to the press): a press at rest tests nothing, so it fails this."""
    max_distance_after_press: Optional[float] = Field(None, gt=0)
    """Every press held the base: its true path from the press to the release is at most this
    (m; the coast of a base braked from driving speed, not a robot that drove on)."""


class PauseEffect(StrictEntry):
    still_within: float = Field(1.0, gt=0)
    """s after the pause from which, until the resume, no duty reaches past the motors' dead
    zone and the base stands still: the tree stops its navigation on its next tick and the wheel
    PID brakes the base in a few ticks (the base coasts a few mm after the last braking tick)."""
    max_motion: float = Field(0.005, gt=0)
    """True displacement allowed from then until the resume, m (settling, not motion)."""


class DropoutEffect(StrictEntry):
    zero_twist_within: float = Field(0.7, gt=0)
    """s from the lidar going dark until the twist handed to the base is zero for good:
    ``nav.navigator.scan_timeout`` (0.5 s) after the last scan (up to one 10 Hz scan period
    before the dropout), plus a control tick."""
    drives_again_within: float = Field(3.0, gt=0)
    """s from the scans' return until autonomy drives the base again (the patrol goes on)."""


class BlindEffect(StrictEntry):
    zero_linear_within: float = Field(0.25, gt=0)
    """s from the lidar going blind until the linear twist handed to the base is zero for good:
    the next revolution (0.1 s) is judged blind on the base tick that takes it (0.1 s)."""
    drives_again_within: float = Field(3.0, gt=0)
    """s from the lidar seeing again until autonomy drives the base again (the patrol goes on)."""


class ClearMapEffect(StrictEntry):
    map_back: float = Field(0.8, gt=0, le=1)
    """The fraction of the cells SLAM's map knew before the reset that it must know again."""
    within: float = Field(20.0, gt=0)
    """s from the reset (the worker respawns ``nav.slam.respawn_delay`` = 1 s after it)."""


class TeleopEffect(StrictEntry):
    settle: float = Field(0.5, ge=0)
    """s from the stick's first message until the true base twist must follow it (the wheel PID
    and the motors' lag)."""
    tolerance: float = Field(0.05, gt=0)
    """Allowed difference between the true mean body twist and the stick's, per component (m/s
    and rad/s)."""


class RestartEffect(StrictEntry):
    engaged: bool = True
    """The restarted runtime's soft stop: engaged (it was engaged before the crash, or the crash
    itself counts as an unclean exit) on every control tick after the restart."""
    still_within: float = Field(1.0, gt=0)
    """s after the crash from which the base must stand still (the wheels coast to a stop)."""
    max_motion: float = Field(0.01, gt=0)
    """True displacement allowed from then to the run's end, m."""


class PeopleExpect(StrictEntry):
    min_clearance: Optional[float] = Field(None, ge=0)
    """Least distance between the robot's body (its footprint and the arm as it stands) and any
    walker's body over every moment the robot moves (base >= 0.05 m/s or turning >= 0.1 rad/s),
    m, ground truth (``mission.jobs.people_log``): a walker that walks into a robot standing
    still is not the robot's doing."""
    contacts: Optional[int] = Field(None, ge=0)
    """Most robot-walker contacts allowed while the robot moves (usually 0)."""
    encounters: Optional[int] = Field(None, ge=0)
    """At least this many times a walker came within 1.0 m of the robot, so a scenario whose
    people never meet the robot fails instead of passing on nothing."""


class FleetExpect(StrictEntry):
    """What a fleet must do (``robots: N``, ``mission.scenario.fleet_file``), judged on ground truth
    (``fleet.scenario_judge``)."""

    robot_contacts: Optional[int] = Field(None, ge=0)
    """Most contacts allowed between two robots' bodies (each pair's onset counts once)."""
    head_on_in_aisle: Optional[int] = Field(None, ge=0)
    """Most head-on meetings allowed: two robots in one aisle at once, closing on each other."""
    pots: Optional[PotSet] = None
    """The mission's pots inspected by some robot: all, how many, or which ids."""
    others_drive_while_stopped: Optional[float] = Field(None, gt=0)
    """While a robot is held by an e-stop, every other robot on patrol drives at least this far
    (m, ground truth): a stop of one robot must not stop the fleet."""

    @field_validator("pots", mode="before")
    @classmethod
    def _pot_set(cls, v: Any) -> Any:
        return pot_set(v)


class EffectsExpect(StrictEntry):
    """Each key judges every event of its kind: the event must have done what it is for."""

    pause: Optional[PauseEffect] = None
    lidar_dropout: Optional[DropoutEffect] = None
    lidar_blind: Optional[BlindEffect] = None
    clear_map: Optional[ClearMapEffect] = None
    teleop: Optional[TeleopEffect] = None
    runtime_crash: Optional[RestartEffect] = None


class Expect(StrictEntry):
    outcome: Optional[Literal["completed", "aborted", "battery_low", "failed"]] = None
    max_sim_time: float = Field(600.0, gt=0)
    """The run must end within this, s of runtime clock; a run still going then is stopped and
    finished ``aborted`` (so ``outcome: aborted`` says "still held at the limit")."""
    pots: Optional[PotsExpect] = None
    anomalies: list[AnomalyExpect] = []
    no_anomalies: list[str] = []
    home: Optional[HomeExpect] = None
    arm: Optional[str] = None
    """The arm's final preset (``home``, ``inspect``, ...)."""
    estop: Optional[EStopExpect] = None
    effects: Optional[EffectsExpect] = None
    """The effect each event of the named kinds must show (``mission.scenario.effects``)."""
    report_files: list[str] = []
    """Files that must exist beside the report."""
    people: Optional[PeopleExpect] = None
    """Clearance and contacts with the world's walkers (spec/world.md)."""
    fleet: Optional[FleetExpect] = None
    """A fleet scenario's contacts, head-on meetings and pots (``mission.scenario.fleet_file``)."""

    @field_validator("arm")
    @classmethod
    def _preset(cls, v: str | None) -> str | None:
        if v is not None and v not in PRESETS:
            raise ValueError(f"must be one of {', '.join(PRESETS)} (got {v!r})")
        return v


class ScenarioFile(StrictEntry):
    name: str = Field(min_length=1)
    description: str = ""
    world: str = "default"
    mission: str = "from-world"
    seed: Optional[int] = None
    robots: Optional[int] = Field(None, ge=1)
    """A fleet scenario: this many robots, r1..rN at the world's spawns (``mission.scenario.fleet_file``)."""
    config: dict[str, Any] = {}
    events: list[Any] = []
    expect: Expect = Expect()


@dataclass
class Scenario:
    """A scenario with everything it names read and checked."""

    path: Path
    spec: ScenarioFile
    world: World
    mission: Mission
    events: list
    config: LupinConfig
    robot_events: dict[str, list] = field(default_factory=dict)
    """A fleet scenario's events by the robot they are addressed to (empty for one robot)."""

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def expect(self) -> Expect:
        return self.spec.expect


def _relative(base: Path, name: str) -> Path:
    p = Path(name)
    return p if p.is_absolute() else base.parent / p


def parse_scenario(data: Any, path: Path, base_config: LupinConfig) -> Scenario:
    source = str(path)
    if not isinstance(data, dict):
        raise InputError(f"{source}: top level: must be a mapping with keys name, expect, ... (got {kind_of(data)})")
    try:
        spec = ScenarioFile.model_validate(data)
    except ValidationError as exc:
        raise InputError("\n".join(f"{source}: {line}" for line in error_lines(exc, data, ScenarioFile))) from None
    try:
        config = with_overrides(base_config, spec.config)
    except ValidationError as exc:
        lines = [f"{source}: config: field '{'.'.join(map(str, e['loc']))}': {e['msg']}" for e in exc.errors()]
        raise InputError("\n".join(lines)) from None
    if spec.seed is not None:
        config = with_seed(config, spec.seed)
    world = load_default_world() if spec.world == "default" else load_world(_relative(path, spec.world))
    mission = mission_from_world(world) if spec.mission == "from-world" else load_mission(_relative(path, spec.mission))
    check_fleet_file(data, spec, len(world.spawn_poses), world.name, source)
    plain, to = addressed(spec.events, spec.robots, source)
    events = parse_events(plain, source, config, world)
    robot_events = {} if spec.robots is None else \
        by_robot(plain, to, spec.robots, lambda mine: parse_events(mine, source, config, world))
    if spec.expect.people is not None and not world.walkers:
        raise InputError(f"{source}: expect: field 'people': the world {world.name!r} has no walkers to judge against")
    return Scenario(path, spec, world, mission, events, config, robot_events)


def load_scenario(path: str | Path, base_config: LupinConfig | None = None) -> Scenario:
    """Read and check a scenario and all it names; ``InputError`` (only) for anything wrong."""
    path = Path(path)
    return parse_scenario(read_yaml(path, "scenario file"), path, base_config or LupinConfig())
