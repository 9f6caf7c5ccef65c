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

import math
import re
from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from hw.errors import InputError
from sim.config import GreenhouseGeometry

DEFAULT_WORLD: Path = Path(__file__).resolve().parent / "worlds" / "default.yaml"
"""The built-in greenhouse (3 rows of 4 pots), found next to this module so it also works
when Lupin is installed rather than run from a checkout."""

ROBOT_RADIUS = 0.22
"""Radius of the circle that encloses the robot's footprint, m. The spawn circle must not touch
a wall, a pot or an obstacle, or the robot would start inside something (spec: "a spawn inside
an obstacle" is impossible geometry)."""

TAG_IDS = range(0, 587)
"""AprilTag 36h11 has 587 codes, ids 0..586. The original robot whitelisted 0..21
(reference/upstream.md) but any valid id of the family can be printed on a plate."""

FLOWERS = ("red", "white", "pink", "none")
"""Flower classes of the HSV detector (reference/upstream.md), plus ``none``: a pot without
a bloom."""

_EPS = 1e-9  # geometry tolerance: exactly touching pots or boxes are allowed


class _Entry(BaseModel):
    """Base of every world entry: strict, because a world file is a contract (spec/world.md).

    ``extra='forbid'`` rejects unknown keys (a typo would otherwise be silently ignored);
    ``strict`` refuses ``x: '1.0'`` and ``tag: true`` instead of coercing them; NaN and
    infinity are never a position.
    """

    model_config = ConfigDict(
        extra="forbid", strict=True, allow_inf_nan=False, use_attribute_docstrings=True
    )


class Floor(_Entry):
    """Interior size of the greenhouse; the floor spans [0, x] x [0, y] and 2 m walls enclose it."""

    x: float = Field(gt=0)
    """Extent along the world x axis (east), m."""
    y: float = Field(gt=0)
    """Extent along the world y axis (north), m."""


class Pose2(_Entry):
    """A planar pose in the ``world`` frame (REP-103: x east, y north, yaw counter-clockwise)."""

    x: float
    """Position east, m."""
    y: float
    """Position north, m."""
    yaw: float = 0.0
    """Heading, rad; 0 looks along +x."""


class Pot(_Entry):
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
    tag: int | None = None
    """AprilTag 36h11 id printed on the plate; ``None`` (key omitted): the pot has no tag."""
    flower: Literal["red", "white", "pink", "none"]
    """Bloom colour, one of the HSV detector's classes, or ``none`` for no bloom."""
    bug: bool = False
    """True: a dark pest spot on the bloom, an anomaly the robot must report."""
    blooms: int = Field(1, ge=1, le=3)
    """How many blooms, 1..3 (ignored for ``flower: none``)."""

    @field_validator("tag")
    @classmethod
    def _tag_in_family(cls, tag: int | None) -> int | None:
        if tag is not None and tag not in TAG_IDS:
            raise ValueError(f"must be an AprilTag 36h11 id, 0..{TAG_IDS[-1]} (got {tag})")
        return tag


class Obstacle(_Entry):
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


class Climate(_Entry):
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


class World(_Entry):
    """A whole greenhouse world file (spec/world.md)."""

    name: str
    """Free text naming the world."""
    floor: Floor
    """Interior size; the floor spans [0, x] x [0, y]."""
    spawn: Pose2
    """Robot start pose, normally in the south aisle."""
    pots: list[Pot]
    """The pots, in any order; ids and tags are unique."""
    obstacles: list[Obstacle] = []
    """Optional extra boxes standing on the floor."""
    climate: dict[int, Climate] = {}
    """Optional climate readings keyed by tag id; every key must be a tag that some pot carries."""


# ---------------------------------------------------------------------------------------------
# Loading


class _UniqueKeyLoader(yaml.SafeLoader):
    """A safe YAML loader that refuses a key repeated in one mapping: plain PyYAML keeps the last
    one silently, which would hide a typo such as two ``x:`` in one pot."""


def _construct_unique_mapping(loader: _UniqueKeyLoader, node: yaml.MappingNode, deep: bool = False):
    loader.flatten_mapping(node)
    seen: set[Any] = set()
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        try:
            duplicate = key in seen
        except TypeError:  # unhashable key: let the base constructor report it
            break
        if duplicate:
            raise yaml.constructor.ConstructorError(
                "while constructing a mapping", node.start_mark,
                f"found duplicate key {key!r}", key_node.start_mark,
            )
        seen.add(key)
    return loader.construct_mapping(node, deep=deep)


_UniqueKeyLoader.add_constructor(
    yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_unique_mapping
)


def load_world(path: str | Path, geometry: GreenhouseGeometry | None = None) -> World:
    """Read, parse and check a world file.

    Raises :class:`InputError` (never another exception) for a missing, unreadable, empty or
    non-YAML file and for every problem :func:`parse_world` finds; the message starts with
    ``path`` as given, so the user sees the file they named.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{source}: world file not found") from None
    except IsADirectoryError:
        raise InputError(f"{source}: is a directory, not a world file") from None
    except UnicodeDecodeError:
        raise InputError(f"{source}: not a YAML world file (not UTF-8 text)") from None
    except OSError as exc:
        raise InputError(f"{source}: cannot read the world file: {exc.strerror or exc}") from None
    try:
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader subclass
    except yaml.YAMLError as exc:
        raise InputError(f"{source}: not valid YAML: {_yaml_reason(exc)}") from None
    if data is None:
        raise InputError(f"{source}: the world file is empty")
    return parse_world(data, source, geometry)


def parse_world(data: Any, source: str, geometry: GreenhouseGeometry | None = None) -> World:
    """Build a :class:`World` from already-parsed YAML data and check it completely.

    ``source`` names where the data came from; it starts every message.
    """
    if not isinstance(data, dict):
        raise InputError(
            f"{source}: top level: must be a mapping with keys name, floor, spawn, pots "
            f"(got {_kind(data)})"
        )
    try:
        world = World.model_validate(data)
    except ValidationError as exc:
        lines = [_format_error(err, data) for err in exc.errors()]
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
        "pots": [p.model_dump(exclude_none=True) for p in world.pots],
    }
    if world.obstacles:
        data["obstacles"] = [o.model_dump() for o in world.obstacles]
    if world.climate:
        data["climate"] = {k: c.model_dump(exclude_none=True) for k, c in world.climate.items()}
    body = yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=120)
    return "# Lupin greenhouse world (spec/world.md): metres, radians, world frame.\n" + body


# ---------------------------------------------------------------------------------------------
# Cross-entry checks


def world_problems(
    world: World,
    geometry: GreenhouseGeometry | None = None,
    robot_radius: float = ROBOT_RADIUS,
) -> list[str]:
    """Every problem that involves more than one entry, one line each (without the file name).

    Pots are circles of ``geometry.pot_radius`` (spec/world.md: ~0.10 m; sim/config.py
    :class:`GreenhouseGeometry` is where the sim fixes it); the robot is a circle of
    ``robot_radius``. The spec calls for rejecting impossible geometry: a pot in or through a
    wall, overlapping pots, a pot in a box, a box outside the floor, a spawn that is outside the
    floor or touches a pot or a box. It also asks for unique ids; tags must be unique too (a tag
    identifies its pot) and climate may only be keyed by a tag that some pot carries.
    """
    r = (geometry or GreenhouseGeometry()).pot_radius
    fx, fy = world.floor.x, world.floor.y
    out: list[str] = []

    first_id: dict[str, int] = {}
    first_tag: dict[int, int] = {}
    for i, pot in enumerate(world.pots):
        where = _pot(i, world)
        if pot.id in first_id:
            out.append(f"{where}: field 'id': duplicate of pots[{first_id[pot.id]}]")
        first_id.setdefault(pot.id, i)
        if pot.tag is not None:
            if pot.tag in first_tag:
                out.append(
                    f"{where}: field 'tag': tag {pot.tag} is already on {_pot(first_tag[pot.tag], world)}"
                )
            first_tag.setdefault(pot.tag, i)
        out += [f"{where}: {p}" for p in _circle_in_floor(pot.x, pot.y, r, fx, fy, "pot")]

    out += _overlapping_pots(world, r)

    for j, box in enumerate(world.obstacles):
        corners = _box_corners(box)
        bad = [c for c in corners if not (-_EPS <= c[0] <= fx + _EPS and -_EPS <= c[1] <= fy + _EPS)]
        if bad:
            cx, cy = bad[0]
            out.append(
                f"obstacles[{j}]: fields 'x', 'y', 'sx', 'sy', 'yaw': the box reaches outside the "
                f"floor: corner ({cx:.2f}, {cy:.2f}) is not in [0, {fx:.2f}] x [0, {fy:.2f}]"
            )
        for i, pot in enumerate(world.pots):
            d = _distance_to_box(pot.x, pot.y, box)
            if d < r - _EPS:
                out.append(
                    f"{_pot(i, world)} overlaps obstacles[{j}]: {_gap(d, r, 'pot')} (fields 'x', 'y')"
                )

    s = world.spawn
    out += [f"spawn: {p}" for p in _circle_in_floor(s.x, s.y, robot_radius, fx, fy, "robot")]
    for i, pot in enumerate(world.pots):
        d, need = math.hypot(pot.x - s.x, pot.y - s.y), robot_radius + r
        if d < need - _EPS:
            got, want = _pair(d, need)
            out.append(
                f"spawn overlaps {_pot(i, world)}: centres {got} m apart, need >= {want} m "
                f"(robot radius {robot_radius:.2f} m + pot radius {r:.2f} m) (fields 'x', 'y')"
            )
    for j, box in enumerate(world.obstacles):
        d = _distance_to_box(s.x, s.y, box)
        if d < robot_radius - _EPS:
            out.append(f"spawn overlaps obstacles[{j}]: {_gap(d, robot_radius, 'robot')} (fields 'x', 'y')")

    for tag in world.climate:
        if tag not in first_tag:
            out.append(f"climate[{tag}]: key {tag}: no pot carries tag {tag}")
    return out


def _overlapping_pots(world: World, r: float) -> list[str]:
    """Pairs of pots closer than two radii; a sweep along x keeps big generated worlds fast."""
    order = sorted(range(len(world.pots)), key=lambda i: world.pots[i].x)
    found: list[tuple[int, int, float]] = []
    for a, i in enumerate(order):
        pi = world.pots[i]
        for j in order[a + 1:]:
            pj = world.pots[j]
            if pj.x - pi.x >= 2 * r:
                break
            d = math.hypot(pj.x - pi.x, pj.y - pi.y)
            if d < 2 * r - _EPS:
                found.append((max(i, j), min(i, j), d))
    out = []
    for later, earlier, d in sorted(found):
        got, want = _pair(d, 2 * r)
        out.append(
            f"{_pot(later, world)} overlaps {_pot(earlier, world)}: centres {got} m apart, "
            f"need >= {want} m (fields 'x', 'y')"
        )
    return out


def _circle_in_floor(x: float, y: float, r: float, fx: float, fy: float, what: str) -> list[str]:
    """Why a circle is not fully inside [0, fx] x [0, fy] (empty list: it is)."""
    out = []
    for field, v, size, low_wall, high_wall in (("x", x, fx, "west", "east"), ("y", y, fy, "south", "north")):
        if size < 2 * r:
            out.append(f"field '{field}': the floor is {size:.2f} m across, too small for a {what} "
                       f"of radius {r:.2f} m")
        elif v < r - _EPS or v > size - r + _EPS:
            wall = low_wall if v < r else high_wall
            out.append(
                f"field '{field}': the {what} (radius {r:.2f} m) crosses the {wall} wall: "
                f"need {r:.2f} <= {field} <= {size - r:.2f} m (got {v:g})"
            )
    return out


def _box_corners(box: Obstacle) -> list[tuple[float, float]]:
    c, s = math.cos(box.yaw), math.sin(box.yaw)
    hx, hy = box.sx / 2, box.sy / 2
    return [(box.x + c * u - s * v, box.y + s * u + c * v) for u in (-hx, hx) for v in (-hy, hy)]


def _distance_to_box(x: float, y: float, box: Obstacle) -> float:
    """Distance from a point to a yawed box's footprint (0 inside it)."""
    c, s = math.cos(box.yaw), math.sin(box.yaw)
    dx, dy = x - box.x, y - box.y
    u, v = c * dx + s * dy, -s * dx + c * dy  # the point in the box frame
    return math.hypot(max(abs(u) - box.sx / 2, 0.0), max(abs(v) - box.sy / 2, 0.0))


def _gap(d: float, need: float, what: str) -> str:
    if d <= 0:
        return f"the {what} centre is inside the box"
    got, want = _pair(d, need)
    return f"the {what} centre is {got} m from the box, need >= {want} m (its radius)"


def _pair(got: float, need: float) -> tuple[str, str]:
    """Format two distances with enough decimals that they visibly differ."""
    for digits in (2, 3, 4, 6):
        a, b = f"{got:.{digits}f}", f"{need:.{digits}f}"
        if a != b:
            return a, b
    return f"{got!r}", f"{need!r}"


def _pot(i: int, world: World) -> str:
    return f"pots[{i}] (id {world.pots[i].id})"


# ---------------------------------------------------------------------------------------------
# Pydantic errors -> one line each


_ENTRY_MODELS: dict[str, type[_Entry]] = {
    "floor": Floor, "spawn": Pose2, "pots": Pot, "obstacles": Obstacle, "climate": Climate,
}
_LISTS = ("pots", "obstacles")
_MAPS = ("climate",)
_TYPES = {
    "float_type": "must be a number", "float_parsing": "must be a number",
    "int_type": "must be an integer", "int_parsing": "must be an integer",
    "int_from_float": "must be an integer", "string_type": "must be text",
    "bool_type": "must be true or false", "bool_parsing": "must be true or false",
    "list_type": "must be a list", "dict_type": "must be a mapping",
    "model_type": "must be a mapping", "model_attributes_type": "must be a mapping",
    "finite_number": "must be a finite number",
}
_BOUNDS = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<="}


def _format_error(err: dict[str, Any], data: dict[str, Any]) -> str:
    """One pydantic error as ``<entry>: field '<name>': <what is wrong>``."""
    loc = list(err["loc"])
    entry, rest = "top level", loc
    if loc and loc[0] in _LISTS and len(loc) > 1 and isinstance(loc[1], int):
        entry, rest = f"{loc[0]}[{loc[1]}]", loc[2:]
        items = data.get(loc[0])
        item = items[loc[1]] if isinstance(items, list) and loc[1] < len(items) else None
        if isinstance(item, dict) and isinstance(item.get("id"), (str, int)):
            entry += f" (id {item['id']})"
    elif loc and loc[0] in _MAPS and len(loc) > 1:
        key = loc[1] if isinstance(loc[1], int) else repr(loc[1])
        entry, rest = f"{loc[0]}[{key}]", loc[2:]
    elif loc and loc[0] in _ENTRY_MODELS and len(loc) > 1:
        entry, rest = str(loc[0]), loc[1:]
    if rest == ["[key]"]:
        return f"{entry}: key {loc[1]!r}: must be an integer tag id"
    what = _describe(err, loc)
    if not rest:
        return f"{entry}: {what}"
    return f"{entry}: field '{'.'.join(str(p) for p in rest)}': {what}"


def _describe(err: dict[str, Any], loc: list[Any]) -> str:
    kind, ctx, got = err["type"], err.get("ctx") or {}, err.get("input")
    if kind == "missing":
        return "missing required key"
    if kind == "extra_forbidden":
        model = _ENTRY_MODELS.get(loc[0]) if len(loc) > 1 else World
        allowed = ", ".join(model.model_fields) if model else ""
        return f"unknown key (allowed: {allowed})" if allowed else "unknown key"
    if kind == "literal_error":
        options = ", ".join(re.findall(r"'([^']*)'", str(ctx.get("expected", ""))))
        return f"must be one of {options} (got {_shown(got)})"
    if kind in _BOUNDS:
        bound = next(iter(ctx.values()))
        return f"must be {_BOUNDS[kind]} {bound:g} (got {_shown(got)})"
    if kind == "value_error":
        return str(err["msg"]).removeprefix("Value error, ")
    if kind in _TYPES:
        return f"{_TYPES[kind]} (got {_shown(got)})"
    return f"{str(err['msg'])[:1].lower()}{str(err['msg'])[1:]} (got {_shown(got)})"


def _shown(value: Any) -> str:
    """A short rendering of an offending value: scalars as written, containers by kind."""
    if value is None:
        return "nothing"
    if isinstance(value, bool):
        return str(value).lower()  # as YAML spells it
    if isinstance(value, (dict, list)):
        return _kind(value)
    return repr(value)


def _kind(value: Any) -> str:
    """A user-facing name for the type of a YAML value."""
    if isinstance(value, bool):
        return f"a boolean ({str(value).lower()})"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, str):
        return f"text {value[:40]!r}"
    if isinstance(value, (int, float)):
        return f"a number ({value!r})"
    if value is None:
        return "nothing"
    return type(value).__name__


def _yaml_reason(exc: yaml.YAMLError) -> str:
    """``line L, column C: problem`` from a PyYAML error, on one line."""
    mark = getattr(exc, "problem_mark", None)
    problem = getattr(exc, "problem", None) or str(exc)
    where = f"line {mark.line + 1}, column {mark.column + 1}: " if mark is not None else ""
    return where + " ".join(str(problem).split())
