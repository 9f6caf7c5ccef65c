"""Greenhouse world files: the models, the loader and the checks (contract: spec/world.md).

A world file says what physically exists in a simulated greenhouse: the floor, the robot's
spawn pose, the pots (with their tag, flower and pest), extra boxes, and what the climate
source returns per tag. The spec requires that unknown keys, missing required keys, duplicate
ids and impossible geometry are rejected "with a message that names the file, the entry and
the field", so every problem becomes one line such as::

    worlds/x.yaml: pots[3] (id P04): field 'flower': must be one of red, white, pink, none (got 'blue')
    worlds/x.yaml: pots[2] (id P03) overlaps pots[1] (id P02): centres 0.15 m apart, need >= 0.20 m (fields 'x', 'y')

and all the lines of a file are raised together as one :class:`hw.errors.InputError` (a user
error: no traceback, DESIGN.md "Errors a user can cause"). Checking happens in two passes:
pydantic checks each entry's keys, types and ranges, then :func:`world_problems` checks what
involves several entries (geometry, duplicate ids and tags, climate keys).

Public API: :class:`World` and its parts, :func:`load_world`, :func:`parse_world`,
:func:`validate_world`, :func:`world_problems`, :func:`dump_world`, :data:`DEFAULT_WORLD`,
:func:`load_default_world`.
"""
from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal, Optional

import yaml
from pydantic import Field, ValidationError

from hw.errors import InputError
from hw.input_file import StrictEntry, error_lines, kind_of, read_yaml
from hw.tag_family import TagId
from sim.config import GreenhouseGeometry
from sim.world_checks import ROBOT_RADIUS, world_problems

DEFAULT_WORLD: Path = Path(__file__).resolve().parent / "worlds" / "default.yaml"
"""The built-in greenhouse (3 rows of 4 pots), found next to this module so it also works
when Lupin is installed rather than run from a checkout."""

FLOWERS = ("red", "white", "pink", "none")
"""Flower classes of the HSV detector (reference/upstream.md), plus ``none``: a pot without
a bloom."""


class Floor(StrictEntry):
    """Interior size of the greenhouse; the floor spans [0, x] x [0, y] and 2 m walls enclose it."""

    x: float = Field(gt=0)
    """Extent along the world x axis (east), m."""
    y: float = Field(gt=0)
    """Extent along the world y axis (north), m."""


class Pose2(StrictEntry):
    """A planar pose in the ``world`` frame (REP-103: x east, y north, yaw counter-clockwise)."""

    x: float
    """Position east, m."""
    y: float
    """Position north, m."""
    yaw: float = 0.0
    """Heading, rad; 0 looks along +x."""


class Pot(StrictEntry):
    """One pot with its plant, the thing the robot inspects."""

    id: str = Field(min_length=1)
    """Unique name of the pot (it keys the mission and the report, spec/report.md)."""
    x: float
    """Pot centre east, m."""
    y: float
    """Pot centre north, m."""
    facing: float
    """Yaw of the pot's inspection side, rad: the outward normal pointing to the aisle the robot
    inspects it from. The tag plate is on this side."""
    tag: TagId | None = None
    """AprilTag 36h11 id printed on the plate; ``None`` (key omitted): the pot has no tag."""
    flower: Literal["red", "white", "pink", "none"]
    """Bloom colour, one of the HSV detector's classes, or ``none`` for no bloom."""
    bug: bool = False
    """True: a pest on the plant, an anomaly the robot must report: a dark spot on a bloom, or on a
    leaf of a plant with no bloom (spec/world.md; where exactly: ``sim.pests``)."""
    blooms: int = Field(1, ge=1, le=3)
    """How many blooms, 1..3 (ignored for ``flower: none``)."""


class Obstacle(StrictEntry):
    """An extra box standing on the floor (a crate, a bench leg, a bucket)."""

    x: float
    """Box centre east, m."""
    y: float
    """Box centre north, m."""
    sx: float = Field(gt=0)
    """Full size along the box's own x axis, m."""
    sy: float = Field(gt=0)
    """Full size along the box's own y axis, m."""
    yaw: float = 0.0
    """Rotation of the box about z, rad."""
    h: float = Field(0.8, gt=0)
    """Height, m. The default 0.8 m stands well above the lidar plane, so the robot sees it."""


CART_FROM_WIDTH = 0.6
"""A walker wider than this pushes a cart, m (spec/world.md ``width``: 0.45 a person, up to 1.2 one
with a cart)."""


class Walker(StrictEntry):
    """A person in the greenhouse (spec/world.md): walking ``path`` and back for ever, or, with a
    path of one point, a worker who stays there."""

    id: str = Field(min_length=1)
    """Unique among the walkers."""
    path: list[Annotated[list[float], Field(min_length=2, max_length=2)]] = Field(min_length=1)
    """Waypoints [x, y], world frame: walked in order, then back (ping-pong); one point: the
    person stays there (a worker at a bench)."""
    speed: float | None = None
    """Walking speed along the path, m/s: 0.2..1.5 (people walk at 0.8 to 1.4), required for a
    path of two or more points; anything (or nothing) for a worker who stays put."""
    pause: float = Field(0.0, ge=0)
    """Seconds standing still at each end of the path."""
    start: float = Field(0.0, ge=0)
    """Sim seconds before the walker sets off."""
    width: float = Field(0.45, ge=0.2, le=1.2)
    """Body width across the shoulders, m: 0.45 for a person; up to 1.2 for one pushing a cart."""
    yields: bool = True
    """True: stops while its next step would come within 0.3 m of the robot (people do not walk
    into a machine); False: walks on regardless (looking at the plants, not at the robot), so
    keeping clear is the robot's job alone."""
    posture: Literal["standing", "crouching"] = "standing"
    """``crouching``: kneeling or squatting at a bench, one compact body about 0.5 x 0.6 m and
    1.0 m tall with no legs apart in the lidar's plane (easily taken for a pot or a crate)."""

    @property
    def pushes_cart(self) -> bool:
        """Wider than ``CART_FROM_WIDTH``: one pushing a cart (the sim builds the cart, and it
        moves with them)."""
        return self.width > CART_FROM_WIDTH


class Climate(StrictEntry):
    """What the sim's climate source returns for one tag (the original robot's "climate data",
    reference/upstream.md). Every field is optional: a report carries only what a source knows
    (spec/report.md shows ``{"temperature": 22.5}``)."""

    temperature: float | None = None
    """Air temperature, deg C."""
    humidity: float | None = Field(None, ge=0, le=100)
    """Relative humidity, %."""
    co2: float | None = Field(None, ge=0)
    """CO2 concentration, ppm."""
    light: float | None = Field(None, ge=0)
    """Illuminance, lux."""
    soil_moisture: float | None = Field(None, ge=0, le=1)
    """Volumetric soil water content, fraction 0..1."""


class World(StrictEntry):
    """A whole greenhouse world file (spec/world.md)."""

    name: str
    """Free text naming the world."""
    floor: Floor
    """Interior size; the floor spans [0, x] x [0, y]."""
    spawn: Pose2
    """Robot start pose, normally in the south aisle."""
    spawns: list[Pose2] = []
    """A fleet's docks, one per robot, the first ``spawn`` (spec/world.md, spec/fleet.md "The
    fleet in the sim"); empty: one robot, at ``spawn``."""
    dock: Optional[Pose2] = None
    """Where the robot charges (issue 31); None: the spawn pose, the robot starts on its dock."""
    pots: list[Pot]
    """The pots, in any order; ids and tags are unique."""
    obstacles: list[Obstacle] = []
    """Optional extra boxes standing on the floor."""
    walkers: list[Walker] = []
    """Optional people walking the aisles."""
    climate: dict[int, Climate] = {}
    """Optional climate readings keyed by tag id; every key must be a tag that some pot carries."""

    @property
    def dock_pose(self) -> Pose2:
        """The charger's pose: ``dock``, or the spawn pose when the file names none."""
        return self.dock or self.spawn

    @property
    def spawn_poses(self) -> list[Pose2]:
        """Each robot's start pose: ``spawns``, or the one ``spawn``."""
        return list(self.spawns) if self.spawns else [self.spawn]

    def for_robot(self, index: int) -> "World":
        """The world as a fleet's robot ``index`` (0-based) knows it: starting and charging at its
        own spawn (``spawns`` are docks), so its default mission, its map frame and its dock are
        its own. A world of one spawn is the world as it is (its ``dock`` kept)."""
        if not self.spawns:
            return self
        pose = self.spawns[index]
        return self.model_copy(update={"spawn": pose, "dock": pose})

    def climate_readings(self) -> dict[int, dict[str, float]]:
        """The climate table as a greenhouse data source hands it out: per tag, the known fields."""
        return {tag: c.model_dump(exclude_none=True) for tag, c in self.climate.items()}


# ---------------------------------------------------------------------------------------------
# Loading

def load_world(path: str | Path, geometry: GreenhouseGeometry | None = None) -> World:
    """Read, parse and check a world file.

    Raises :class:`InputError` (never another exception) for a missing, unreadable, empty or
    non-YAML file and for every problem :func:`parse_world` finds; the message starts with
    ``path`` as given, so the user sees the file they named.
    """
    data = read_yaml(path, "world file")
    return parse_world(data, str(path), geometry)


def parse_world(data: Any, source: str, geometry: GreenhouseGeometry | None = None) -> World:
    """Build a :class:`World` from already-parsed YAML data and check it completely.

    ``source`` names where the data came from; it starts every message.
    """
    if not isinstance(data, dict):
        raise InputError(
            f"{source}: top level: must be a mapping with keys name, floor, spawn, pots "
            f"(got {kind_of(data)})"
        )
    try:
        world = World.model_validate(data)
    except ValidationError as exc:
        lines = error_lines(exc, data, World)
        raise InputError("\n".join(f"{source}: {line}" for line in lines)) from None
    validate_world(world, source, geometry)
    return world


def validate_world(
    world: World,
    source: str,
    geometry: GreenhouseGeometry | None = None,
    robot_radius: float = ROBOT_RADIUS,
) -> None:
    """Raise :class:`InputError` listing every cross-entry problem of ``world`` (see
    :func:`world_problems`); return quietly when there is none."""
    problems = world_problems(world, geometry, robot_radius)
    if problems:
        raise InputError("\n".join(f"{source}: {p}" for p in problems))


def load_default_world() -> World:
    """The built-in greenhouse, :data:`DEFAULT_WORLD`."""
    return load_world(DEFAULT_WORLD)


def dump_world(world: World) -> str:
    """YAML text of ``world`` that :func:`load_world` reads back equal.

    Omitted values mean what the spec says they mean: no ``tag`` key is a pot without a tag, a
    climate field left out is unknown; empty ``obstacles``/``climate`` sections are dropped.
    Pots, obstacles and climate entries are written one per line to keep big worlds readable.
    """
    data: dict[str, Any] = {
        "name": world.name,
        "floor": world.floor.model_dump(),
        "spawn": world.spawn.model_dump(),
        **({"spawns": [p.model_dump() for p in world.spawns]} if world.spawns else {}),
        **({"dock": world.dock.model_dump()} if world.dock is not None else {}),
        "pots": [p.model_dump(exclude_none=True) for p in world.pots],
    }
    if world.obstacles:
        data["obstacles"] = [o.model_dump() for o in world.obstacles]
    if world.walkers:
        data["walkers"] = [w.model_dump(exclude_none=True) for w in world.walkers]
    if world.climate:
        data["climate"] = {k: c.model_dump(exclude_none=True) for k, c in world.climate.items()}
    body = yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=120)
    return "# Lupin greenhouse world (spec/world.md): metres, radians, world frame.\n" + body
