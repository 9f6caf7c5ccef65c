"""The simulated greenhouse that the robots share: one model, one engine, one clock beat.

``SimScene(world, sim_config, names)`` compiles the world with one robot per name (``("",)``:
one robot under the robot file's own names, the model every single-robot run has always had;
a fleet's ``("r1", "r2", ...)``: each copy under ``<name>/``, ``sim.greenhouse``) and owns what
is the world's rather than a robot's: the engine every robot's clock advances (idempotent for a
time already reached, so runtimes in lock-step share it), the one renderer pool every camera
draws with (each robot's cameras render the others), the walkers (they stop short of the
nearest robot), and the pots as faults move them. Each ``sim.backend.SimRobot`` on it joins
``robots``.

Judging reads it too, never the runtimes: each robot's true pose (``truths``) and which robots
touch each other now (``robot_contacts``; the chassis collide with each other, contype 2 on 2).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Sequence

import mujoco

from hw.odometry import Pose2D
from hw.wall_clock import WallPace
from sim.cameras import RendererPool
from sim.config import SimConfig
from sim.engine import Engine
from sim.greenhouse import build_greenhouse
from sim.walkers import SimWalkers
from sim.world import World

if TYPE_CHECKING:
    from sim.backend import SimRobot


def prefix(name: str) -> str:
    """The robot's name prefix in the model: none for the one robot of a single run."""
    return f"{name}/" if name else ""


class SimScene:
    def __init__(self, world: World, sim_config: SimConfig, names: Sequence[str] = ("",)):
        if len(names) > len(world.spawn_poses) and tuple(names) != ("",):
            raise ValueError(f"{len(names)} robots but the world {world.name!r} has {len(world.spawn_poses)} spawns")
        self.world, self.names = world, tuple(names)
        self.engine = Engine(build_greenhouse(world, sim_config.geometry, [prefix(n) for n in names]), sim_config)
        self.advance: Callable[[float], None] = self._paced() if sim_config.realtime else self.engine.advance_to
        """What every robot's clock advances the physics with (paced to the wall clock when
        ``sim.realtime``): one pace for the scene, so robots never pace apart."""
        self.renderers = RendererPool(self.engine)
        self.robots: dict[str, SimRobot] = {}
        self.pots = {p.id: (p.x, p.y) for p in world.pots}
        """Each pot's centre (world frame), where it stands now (faults move them)."""
        self.walkers = SimWalkers(self.engine, world.walkers, self.robot_positions)
        if world.walkers:
            self.engine.attach(self.walkers)

    def _paced(self) -> Callable[[float], None]:
        pace, engine = WallPace(self.engine.time), self.engine

        def advance(t: float) -> None:
            pace.wait(t)
            engine.advance_to(t)

        return advance

    def robot_positions(self) -> list[tuple[float, float]]:
        """Every robot's true (x, y), world frame (the walkers keep clear of each)."""
        return [(p.x, p.y) for p in self.truths().values()]

    def truths(self) -> dict[str, Pose2D]:
        """Each robot's ground-truth base pose, world frame (judging only)."""
        return {name: robot.truth() for name, robot in self.robots.items()}

    def robot_contacts(self) -> list[tuple[str, str]]:
        """The pairs of robots (names, sorted) whose chassis touch right now (judging only)."""
        chassis = {robot.chassis: name for name, robot in self.robots.items()}
        pairs = set()
        for a, b in self.engine.data.contact.geom[:self.engine.data.ncon]:
            if int(a) in chassis and int(b) in chassis:
                pairs.add(tuple(sorted((chassis[int(a)], chassis[int(b)]))))
        return sorted(pairs)

    def geom_name(self, geom: int) -> str:
        return mujoco.mj_id2name(self.engine.model, mujoco.mjtObj.mjOBJ_GEOM, geom) or f"geom {geom}"

    def close(self) -> None:
        self.renderers.close()
