"""Mission files (contract: spec/mission.md): what an operator writes to patrol pots.

Read and checked like world files (``hw.input_file``): strict keys and types, every problem one
line naming the file, the entry and the field, all raised together as one ``InputError`` before
the robot moves::

    morning.yaml: pots[2] (id P03): field 'facing': must be a number (got 'south')
    morning.yaml: pots[4] (id P05) has the same tag 3 as pots[2] (id P03) (field 'tag')

Poses are in the ``map`` frame: in SLAM mode its origin is the dock, the robot's pose when the
runtime started. :func:`mission_from_world` writes the mission that patrols every pot of a sim
world in that frame; ``mission.patrol.visit_order`` decides the order the pots are visited in.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, Optional

import yaml
from pydantic import Field, ValidationError

from hw.errors import InputError
from hw.input_file import StrictEntry, error_lines, kind_of, read_yaml
from hw.odometry import Pose2D
from hw.tag_family import TagId
from mission.approach import STANDOFF, approach_pose
from nav.frames import compose, inverse

if TYPE_CHECKING:  # only named: a mission file never needs the simulator
    from sim.world import World


class Home(StrictEntry):
    x: float = 0.0
    """Map-frame x, m (0: the dock)."""
    y: float = 0.0
    """Map-frame y, m."""
    yaw: float = 0.0
    """Heading, rad."""


class MissionPot(StrictEntry):
    id: str = Field(min_length=1)
    """The pot's name: it keys the report."""
    x: float
    """Pot centre, map frame, m."""
    y: float
    """Pot centre, map frame, m."""
    facing: float
    """Yaw of the pot's inspection side, rad, as in the world file: the approach pose stands
    ``standoff`` out along it, looking back at the pot."""
    tag: Optional[TagId] = None
    """Expected AprilTag id; a different id read there is a ``tag_mismatch`` anomaly."""


class Mission(StrictEntry):
    name: str = Field(min_length=1)
    """Names the mission in its report."""
    home: Home = Home()
    """Where the patrol ends, and where low battery sends the robot."""
    standoff: float = Field(STANDOFF, gt=0)
    """Approach distance from the pot centre along its facing, m."""
    retries: int = Field(2, ge=1)
    """Navigation attempts per pot before it is marked failed."""
    nav_timeout: float = Field(60.0, gt=0)
    """Seconds per navigation attempt."""
    return_home: bool = True
    """Drive home at the end."""
    pots: list[MissionPot] = Field(min_length=1)
    """The pots, visited in this order unless ``order: nearest``."""
    order: Literal["as_listed", "nearest", "shortest"] = "as_listed"
    """``nearest``: greedy nearest-neighbour from the robot's pose at the start; ``shortest``: the
    shortest tour the planner finds over the map (``mission.patrol.visit_order``)."""

    def approach(self, pot: MissionPot) -> tuple[float, float, float]:
        """The pot's approach pose (x, y, yaw), map frame."""
        p = approach_pose(pot.x, pot.y, pot.facing, self.standoff)
        return p.x, p.y, p.yaw


def _problems(m: Mission) -> list[str]:
    """What involves several entries: duplicate ids and duplicate tags."""
    out, ids, tags = [], {}, {}
    for i, pot in enumerate(m.pots):
        here = f"pots[{i}] (id {pot.id})"
        if pot.id in ids:
            out.append(f"{here}: field 'id': {pot.id!r} is already used by {ids[pot.id]}")
        ids.setdefault(pot.id, here)
        if pot.tag is not None:
            if pot.tag in tags:
                out.append(f"{here} has the same tag {pot.tag} as {tags[pot.tag]} (field 'tag')")
            tags.setdefault(pot.tag, here)
    return out


def parse_mission(data: Any, source: str) -> Mission:
    """A checked :class:`Mission` from parsed YAML; ``source`` starts every message."""
    if not isinstance(data, dict):
        raise InputError(f"{source}: top level: must be a mapping with keys name, pots (got {kind_of(data)})")
    try:
        mission = Mission.model_validate(data)
    except ValidationError as exc:
        raise InputError("\n".join(f"{source}: {line}" for line in error_lines(exc, data, Mission))) from None
    problems = _problems(mission)
    if problems:
        raise InputError("\n".join(f"{source}: {p}" for p in problems))
    return mission


def load_mission(path: str | Path) -> Mission:
    """Read and check a mission file; ``InputError`` (only) for anything wrong with it."""
    return parse_mission(read_yaml(path, "mission file"), str(path))


def dump_mission(m: Mission) -> str:
    """YAML that :func:`load_mission` reads back equal; one pot per line."""
    data = m.model_dump()
    data["pots"] = [p.model_dump(exclude_none=True) for p in m.pots]
    body = yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=140)
    return "# Lupin patrol mission (spec/mission.md): metres, radians, map frame (origin: the dock).\n" + body


def _r(v: float) -> float:
    return round(v, 6) + 0.0  # no -0.0 in the file


def mission_from_world(world: World, name: str | None = None) -> Mission:
    """Every pot of ``world``, in the map frame of a robot starting at the world's spawn pose
    (the origin), home at the world's dock (the spawn unless it names one), tags as printed, in
    the shortest order."""
    start = inverse(Pose2D(world.spawn.x, world.spawn.y, world.spawn.yaw))
    pots = []
    for p in world.pots:
        q = compose(start, Pose2D(p.x, p.y, p.facing))
        pots.append(MissionPot(id=p.id, x=_r(q.x), y=_r(q.y), facing=_r(q.yaw), tag=p.tag))
    d = world.dock_pose
    dock = compose(start, Pose2D(d.x, d.y, d.yaw))
    return Mission(name=name or f"{world.name}-patrol", pots=pots, order="shortest",
                   home=Home(x=_r(dock.x), y=_r(dock.y), yaw=_r(dock.yaw)))
