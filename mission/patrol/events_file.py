"""Events files (contract: spec/events.md): scripted operator actions and faults for a sim run.

A YAML list; ``at`` is seconds of runtime clock since the mission started. Read like mission
files (``hw.input_file``): strict keys and types, every problem one line naming the file, the
entry (with its action) and the field, all raised together before the robot moves::

    storm.yaml: events[2] (do servo_stall): field 'joint': must be one of shoulder_pan, ... (got 'knee')
    storm.yaml: events[4]: unknown action 'reboot' (known: estop, soft_estop, ...)

Beyond spec/events.md, two fields the spec leaves out and the issue's faults need:
``servo_stall`` takes ``mode: unload | latch`` (default ``unload``, the spec's "goes limp"), and
``camera_dropout {camera, duration}`` makes a camera deliver no frames, as a USB camera that
stalls does. Same-instant events apply in file order; :func:`load_events` returns them sorted by
``at`` (stable). Any event may add ``when_moving: V``: it then waits from ``at`` for the first
control tick at which the base drives at V m/s or faster (``mission.jobs.events``).
"""
from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import Field, TypeAdapter, ValidationError

from hw.errors import InputError
from hw.input_file import StrictEntry, describe, kind_of, read_yaml, shown
from mission.runtime.config import LupinConfig
from sim.greenhouse import SPARE_BOXES

CAMERAS = ("front", "wrist")
TELEOP_SOURCES = ("joy", "manual")


class _Event(StrictEntry):
    at: float = Field(ge=0)
    """Seconds of runtime clock since the mission started."""
    when_moving: Optional[float] = Field(None, gt=0)
    """Fire at the first control tick at or after ``at`` at which the base drives at this speed
    or faster (m/s, its wheel odometry), as a tester who waits for the robot to move would: a
    press "while driving" stays one when the patrol's timing changes."""


class EStop(_Event):
    do: Literal["estop"]
    engaged: bool
    """The physical button (through the e-stop bridge): pressed or released."""


class SoftEStop(_Event):
    do: Literal["soft_estop"]
    engaged: bool
    """The operator's soft stop."""


class Resume(_Event):
    do: Literal["resume"]


class Pause(_Event):
    do: Literal["pause"]


class LidarDropout(_Event):
    do: Literal["lidar_dropout"]
    duration: float = Field(gt=0)


class LidarBlind(_Event):
    do: Literal["lidar_blind"]
    duration: float = Field(gt=0)
    """Seconds the scans arrive with every return invalid (covered, sun)."""


class ServoStall(_Event):
    do: Literal["servo_stall"]
    joint: str
    mode: Literal["unload", "latch"] = "unload"
    """``unload``: the servo goes limp (the arm re-loads it); ``latch``: it ignores commands."""


class Battery(_Event):
    do: Literal["battery"]
    voltage: Optional[float] = Field(gt=0)
    """Forced pack voltage, V; null gives the pack back to the battery model."""


class BatteryDrain(_Event):
    do: Literal["battery_drain"]
    load: float = Field(gt=0)
    """Amps drawn from the pack beyond the robot's own work (a stuck wheel, a short)."""
    duration: float = Field(gt=0)
    """Seconds the extra load lasts."""


class ClearMap(_Event):
    do: Literal["clear_map"]


class Teleop(_Event):
    do: Literal["teleop"]
    source: Literal["joy", "manual"]
    vx: float = 0.0
    vy: float = 0.0
    wz: float = 0.0
    duration: float = Field(gt=0)
    """Seconds the source publishes (at ``TELEOP_RATE``); the mux times it out after."""


class PlaceBox(_Event):
    do: Literal["place_box"]
    x: float
    y: float
    sx: float = Field(gt=0)
    sy: float = Field(gt=0)
    yaw: float = 0.0


class ControllerRace(_Event):
    do: Literal["controller_race"]
    controllers: list[str] = Field(min_length=1)
    state: Literal["missing", "unconfigured", "inactive"]


class CameraDropout(_Event):
    do: Literal["camera_dropout"]
    camera: Literal["front", "wrist"]
    duration: float = Field(gt=0)


class MovePot(_Event):
    do: Literal["move_pot"]
    pot: str = Field(min_length=1)
    """The world's pot id."""
    dx: float = 0.0
    dy: float = 0.0
    """Shift of its centre, world frame, m."""
    dyaw: float = 0.0
    """Turn about its centre, rad (its plate turns with it)."""


class WalkerEvent(_Event):
    do: Literal["walker"]
    walker: str = Field(min_length=1)
    """The world's walker id."""
    moving: bool
    """False: the walker stops where it is (someone stops to talk); true: walks on."""


class RuntimeCrash(_Event):
    do: Literal["runtime_crash"]
    """The runtime process dies and its service restarts it: what it held in memory is gone (the
    patrol, the goal, every twist on the mux, the soft stop as it stood) and it starts again
    from what it persisted in its state directory."""


class HistoryDown(_Event):
    do: Literal["history_down"]
    duration: float = Field(gt=0)
    """Seconds the history's database cannot be reached (a farm server down, the WiFi gone)."""


EVENT_TYPES = (EStop, SoftEStop, Resume, Pause, LidarDropout, LidarBlind, ServoStall, Battery, BatteryDrain, ClearMap, Teleop, PlaceBox,
               ControllerRace, CameraDropout, MovePot, WalkerEvent, RuntimeCrash, HistoryDown)
ACTIONS = {t.model_fields["do"].annotation.__args__[0]: t for t in EVENT_TYPES}
Event = Annotated[Union[EVENT_TYPES], Field(discriminator="do")]
_EVENTS = TypeAdapter(list[Event])


def _error_line(err: dict[str, Any], data: list) -> str:
    loc = list(err["loc"])
    if not loc:
        return f"top level: must be a list of events (got {kind_of(data)})"
    entry = f"events[{loc[0]}]"
    if err["type"] == "union_tag_invalid":
        return f"{entry}: unknown action {shown(err['ctx']['tag'])} (known: {', '.join(ACTIONS)})"
    if err["type"] == "union_tag_not_found":
        return f"{entry}: field 'do': missing required key (one of {', '.join(ACTIONS)})"
    if err["type"] in ("model_type", "model_attributes_type"):
        return f"{entry}: must be a mapping such as {{at: 10.0, do: pause}} (got {shown(err.get('input'))})"
    action, rest = loc[1], loc[2:]
    what = describe(err, ACTIONS.get(action))
    return f"{entry} (do {action}): field '{'.'.join(str(p) for p in rest)}': {what}" if rest else f"{entry} (do {action}): {what}"


def _problems(events: list, config: LupinConfig, pots: frozenset[str] | None,
              walkers: frozenset[str] | None) -> list[str]:
    """What the schema cannot know: the robot's joints and controllers, the sim's spare boxes,
    whether there is a live map, the world's pots (when the world is known)."""
    joints, controllers = tuple(config.hw.servos.joints), tuple(config.hw.controllers)
    out, boxes = [], 0
    for i, e in enumerate(events):
        here = f"events[{i}] (do {e.do})"
        if isinstance(e, ServoStall) and e.joint not in joints:
            out.append(f"{here}: field 'joint': must be one of {', '.join(joints)} (got {e.joint!r})")
        if isinstance(e, ControllerRace):
            unknown = [c for c in e.controllers if c not in controllers]
            if unknown:
                out.append(f"{here}: field 'controllers': unknown {', '.join(map(repr, unknown))} "
                           f"(known: {', '.join(controllers)})")
        if isinstance(e, ClearMap) and not config.nav.slam:
            out.append(f"{here}: the config localises on a saved map (nav.slam false): there is no live map to clear")
        if isinstance(e, MovePot) and pots is not None and e.pot not in pots:
            out.append(f"{here}: field 'pot': the world has no pot {e.pot!r}")
        if isinstance(e, WalkerEvent) and walkers is not None and e.walker not in walkers:
            known = ", ".join(sorted(walkers)) or "none"
            out.append(f"{here}: field 'walker': the world has no walker {e.walker!r} (walkers: {known})")
        if isinstance(e, PlaceBox):
            boxes += 1
            if boxes > SPARE_BOXES:
                out.append(f"{here}: at most {SPARE_BOXES} boxes can be placed in one run")
    return out


def parse_events(data: Any, source: str, config: LupinConfig, world=None) -> list:
    """Checked events from parsed YAML, sorted by ``at`` (file order at the same instant);
    ``world`` (the sim's, when known): its pot and walker ids are the ones ``move_pot`` and
    ``walker`` must name (read from it, so this module never needs the sim)."""
    if not isinstance(data, list):
        raise InputError(f"{source}: top level: must be a list of events such as - {{at: 10.0, do: pause}} "
                         f"(got {kind_of(data)})")
    try:
        events = _EVENTS.validate_python(data)
    except ValidationError as exc:
        raise InputError("\n".join(f"{source}: {_error_line(err, data)}" for err in exc.errors())) from None
    pots = None if world is None else frozenset(p.id for p in world.pots)
    walkers = None if world is None else frozenset(w.id for w in world.walkers)
    problems = _problems(events, config, pots, walkers)
    if problems:
        raise InputError("\n".join(f"{source}: {p}" for p in problems))
    return sorted(events, key=lambda e: e.at)


def load_events(path: str | Path, config: LupinConfig, world=None) -> list:
    """Read and check an events file; ``InputError`` (only) for anything wrong with it."""
    data = read_yaml(path, "events file")
    return parse_events(data, str(path), config, world)
