"""`lupin fleet patrol`: the job round the dispatcher, its inputs checked before any robot moves.

What the dispatcher needs besides the robots (spec/fleet.md "The fleet patrol"):

* the mission (``--mission M``), in the fleet's frame: the first dock's;
* each robot's dock in that frame: ``fleet.docks`` in the config on a farm, else the sim world's
  ``spawns`` (``--world W``, the file ``lupin fleet sim`` was given), robot ``rK`` at the K-th;
* the map the split measures path lengths on: ``--map MAP.yaml`` (a saved map in the mission's
  frame) or, with none, the world's plan (``fleet.fleet_map.plan_of_world``).

Bad input (files, names, a robot with no dock, none up) is one ``InputError`` naming it.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

from fleet.assign import Pose
from fleet.dispatcher import Dispatcher, write_results
from fleet.fleet_map import cost_grid, plan_of_world
from hw.errors import InputError
from mission.link.fleet_config import spawn_docks
from mission.link.session import TlsFiles, open_session, session_config
from mission.patrol.mission_file import Mission, load_mission
from mission.runtime.config import LupinConfig
from nav.map_io import load_map
from nav.occupancy import OccupancyMap

JOIN_WAIT = 3.0
"""Seconds to wait for the robots' liveliness tokens (all of --robots): the roster's history answers at once,
a robot joining as the dispatcher starts within a second."""


@dataclass(frozen=True)
class Inputs:
    mission: Mission
    docks: dict[str, Pose]
    occupancy: OccupancyMap
    where_map: str
    """Where the map came from, for the first line printed."""


def read_inputs(mission_path: Path, world_path: Path | None, map_path: Path | None, config: LupinConfig) -> Inputs:
    mission = load_mission(mission_path)
    world = None
    if config.fleet.docks:
        docks = {r: tuple(map(float, p)) for r, p in config.fleet.docks.items()}
    else:
        world = _world(world_path)
        docks = world_docks(world)
    if map_path is not None:
        return Inputs(mission, docks, load_map(map_path), f"map {map_path}")
    if world is None:
        world = _world(world_path)
    first = world.spawn_poses[0]
    return Inputs(mission, docks, plan_of_world(world, (first.x, first.y, first.yaw), config.nav.costmap.resolution),
                  f"the plan of world {world.name!r}")


def world_docks(world) -> dict[str, Pose]:
    """The sim world's ``spawns`` as the docks of r1, r2, ... in the first one's frame."""
    return spawn_docks(world.spawn_poses)


def _world(path: Path | None):
    from sim.world import load_world  # the sim's file format only; never the sim

    if path is None:
        raise InputError("lupin fleet patrol: give --world W (the sim's world: its spawns are the docks, its plan the "
                         "map), or fleet.docks in the config and --map MAP.yaml on a farm")
    return load_world(path)


def robots_option(text: str | None) -> list[str] | None:
    if text is None:
        return None
    names = [n.strip() for n in text.split(",") if n.strip()]
    bad = [n for n in names if not re.match(r"^[A-Za-z0-9_-]+$", n)]
    if not names or bad:
        raise InputError(f"--robots {text}: expected robot names, comma-separated (e.g. r1,r2)")
    return sorted(set(names))


def fleet_patrol(inputs: Inputs, endpoint: str, tls: TlsFiles | None, robots: Sequence[str] | None, out: Path,
                 config: LupinConfig, say: Callable[[str], None], deadline_s: float | None = None) -> dict:
    """Run the fleet patrol to its end; the fleet summary (``fleet.json``'s)."""
    session = open_session(session_config("connect", endpoint, tls), "connect", endpoint, "--connect")
    d = Dispatcher(session, inputs.mission, inputs.docks, cost_grid(inputs.occupancy, config.nav.costmap),
                   inputs.occupancy, config.fleet.handover_after, say=say)
    try:
        up = d.wait_for_robots(robots, JOIN_WAIT)
        say(f"{len(inputs.mission.pots)} pots of {inputs.mission.name!r} between {', '.join(up)} "
            f"(split on {inputs.where_map})")
        d.start(up)
        finished = d.run(None if deadline_s is None else d.clock() + deadline_s)
        if not finished:
            say("the fleet patrol did not end in time: the report says how far it got")
        return write_results(out, d)
    finally:
        d.close()
        session.close()
