"""What an operator sees of a robot: the console's view model, filled from the link's telemetry.

The runtime publishes topics (``mission.link.keys``); a client folds each message into one
:class:`RobotView` with :meth:`RobotView.apply`. The console draws only from a ``RobotView``
and acts only through a :class:`Commands` object, so it runs the same over Zenoh, against an
in-process runtime, or in a test against a hand-made view.

Every field is plain data (JSON on the wire), map frame, SI units, radians.
"""
from __future__ import annotations

import math

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from nav.grid_geometry import GridGeometry

#: Commands the runtime answers (``lupin/<robot>/cmd/<name>``) and their arguments.
COMMANDS: dict[str, str] = {
    "estop": "engaged: bool (engaging is allowed without the token)",
    "resume": "",
    "pause": "",
    "mission_start": "mission: optional mission (spec/mission.md as a mapping); default every pot",
    "mission_abort": "",
    "teleop": "vx, vy, wz: float (m/s, rad/s); source: manual (default) | joy (a gamepad's dead-man)",
    "arm_preset": "name: a preset (home, zero, tuck, inspect, ...)",
    "gripper": "action: open | close | angle, deg: float for angle (-30 open .. +30 closed)",
    "clear_map": "",
    "heal": "",
    "snapshot": "camera: front | wrist -> JPEG bytes",
    "history": "query: patrols | pot | changes | pests, pot, mission, last, limit -> JSON (mission.history.answers)",
    "report": "-> the current or last patrol's report.json (spec/report.md; the fleet dispatcher's)",
    "arm_calibrate": "action: start | commit | cancel | status -> JSON: phase, joints, note, outcomes (hw only)",
}


class Commands(Protocol):
    """How a console acts on a robot. Each returns None when accepted, else the refusal."""

    def send(self, command: str, /, **args: Any) -> str | None: ...

    def snapshot(self, camera: str) -> bytes | None: ...


@dataclass
class PotView:
    id: str
    x: float
    y: float
    status: str = "pending"
    """pending | active | inspected | failed | skipped."""
    tag: int | None = None
    flower: str | None = None
    blooms: int = 0
    anomalies: list[str] = field(default_factory=list)


@dataclass
class PersonView:
    """One person the robot's tracker follows, map frame (``mission.link.telemetry.PERSON_FIELDS``)."""

    id: int
    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0
    """Velocity, m/s (0 for someone standing)."""
    radius: float = 0.25
    confidence: float = 1.0
    """0..1: how sure the tracker is that this is a person."""
    walked: bool = False
    """The distance rules act on them (they have walked; ``mission.runtime.people``)."""

    @property
    def speed(self) -> float:
        return math.hypot(self.vx, self.vy)

    @classmethod
    def row(cls, r) -> "PersonView":
        """From one wire row (id, x, y, vx, vy, radius, confidence, walked); a rounded-away
        number (None on the wire) reads as 0."""
        i, x, y, vx, vy, radius, confidence, walked = r
        return cls(int(i), float(x), float(y), float(vx or 0.0), float(vy or 0.0), float(radius or 0.0),
                   float(confidence or 0.0), bool(walked))


@dataclass
class GridView:
    """An occupancy grid as the console holds it: int8 -1 unknown / 0..100, [iy, ix]."""

    data: np.ndarray
    resolution: float
    origin_x: float
    origin_y: float

    @property
    def geometry(self) -> GridGeometry:
        return GridGeometry.of(self.data, self.resolution, self.origin_x, self.origin_y)


@dataclass
class OtherRobot:
    """Another robot of the fleet as the console shows it beside the robot it follows: where it
    is and where it is going, in the map frame the fleet shares (spec/fleet.md)."""

    robot: str
    pose: tuple[float, float, float]
    plan: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))


@dataclass
class RobotView:
    robot: str = ""
    t: float = 0.0
    """Runtime time of the newest telemetry."""
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    mux_source: str = "idle"
    monitor_action: str = "none"
    """The collision monitor's last verdict: none, slowdown, approach, stop or blind."""
    monitor_nearest: float = math.inf
    monitor_fault: str | None = None
    """Why the monitor cannot trust the lidar: ``lidar_blind``, ``lidar_stale`` or None."""
    monitor_enabled: bool = True
    """False: the robot runs without its collision monitor (``--no-collision-monitor``)."""
    """Its nearest point in the direction of travel, m."""
    estop_engaged: bool = False
    estop_latched: bool = False
    estop_why: str = ""
    """Why the soft stop came up engaged when the runtime started (a crash, or left engaged);
    '' otherwise or once an operator released it."""
    battery_voltage: float = float("nan")
    battery_percentage: float = float("nan")
    battery_current: float = float("nan")
    """Pack current, A (the power monitor's)."""
    battery_low: bool = False
    controllers: dict[str, str] = field(default_factory=dict)
    nav_state: str = "idle"
    nav_reason: str = ""
    goal: tuple[float, float, float] | None = None
    plan: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    """(N, 2) map-frame points of the current global plan."""
    mission_state: str = "idle"
    """idle | running | paused | estop | done."""
    mission_name: str = ""
    mission_step: str = ""
    mission_outcome: str = ""
    charge: float = float("nan")
    """The patrol's energy budget: the pack's charge, 0..1 (nan: no patrol, or no reading yet)."""
    charge_at_dock: float = float("nan")
    """The charge the budget expects on reaching the dock after the next pot, 0..1."""
    heading_home: str = ""
    """Why the patrol is heading home to charge ('' while it is not)."""
    tree: str = ""
    """py_trees' unicode tree with statuses."""
    pots: list[PotView] = field(default_factory=list)
    grid: GridView | None = None
    costmap: GridView | None = None
    """The inflated global costmap (0..100 scaled cost) for shading."""
    scan: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    """(N, 2) map-frame points of the latest lidar scan."""
    people: list[PersonView] = field(default_factory=list)
    """The tracker's people as of ``t`` (empty when nobody is tracked or no tracker runs)."""
    log: list[str] = field(default_factory=list)
    connected: bool = False
    fleet: list[str] = field(default_factory=list)
    """The robots up on the router, in the order keys 1-9 pick them (``mission.link.fleet_link``);
    empty on a robot's own link."""
    others: list[OtherRobot] = field(default_factory=list)
    """Every other robot up whose telemetry is fresh (the fleet view: all of them on one map)."""
