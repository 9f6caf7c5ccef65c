"""`lupin fleet sim`: one simulated greenhouse, a runtime per robot, all in lock-step.

The robots share one MuJoCo world (``sim.scene``: they see each other on the lidar and the
cameras, their chassis collide), and each has all a robot has: its own HAL on its own parts,
controllers, scheduler, state directory, navigator, service and, joined to the fleet's router,
its own link under its own name (spec/fleet.md "The fleet in the sim"). Nothing passes between
them but through the router.

Lock-step: the runtime whose next task is due first takes the next step (ties in robot order),
so the shared engine is always exactly at the time each task runs for, never ahead of any
runtime, and a fleet's run is a function of its seed like one robot's. Real time (``sim.realtime``)
paces that one engine to the wall clock; ``--fast`` lets it run as fast as the machine allows.
"""
from __future__ import annotations

import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from mission.history.store import History
from mission.jobs.serve import Service, run_service
from mission.jobs.sim_serve import start_sim_service
from mission.link.fleet_config import spawn_docks
from mission.link.server import LinkServer
from mission.link.session import TlsFiles
from mission.link.telemetry import LOGGING_ROBOT
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world
from sim.scene import SimScene
from sim.world import World


LINK_LAG = 0.3
"""Sim seconds a robot's link may lag the others' poses: three of their 10 Hz poses
(``mission.link.peers``). Lock-step runs the engine as fast as the machine allows, so a pose on
the router's way took sim seconds, not milliseconds: on a loaded machine (CI,
``tests/fleet/test_fleet_aisles.py``) r1 saw r2 metres from where r2 had said it stood, took it
for a person, and its way home stayed closed to it. On robots the link's delay is a few ms;
here it is held to what a robot's would be."""
HEAR_WAIT = 1.0
"""Seconds a step waits for them at most (a robot whose link is down is silent after
``peers.SILENT`` and no longer waited for)."""


@dataclass
class FleetSim:
    scene: SimScene
    services: dict[str, Service]
    """Each robot's service, by name, in robot order."""
    links: list[LinkServer] = field(default_factory=list)
    _peers: dict = field(default_factory=dict)
    """Each joined robot's ``mission.link.peers.Peers``, by name."""

    def step(self) -> None:
        """One step of the runtime due first, its log records its own (``LOGGING_ROBOT``); on a
        router, once its link has heard the others' poses of ``LINK_LAG`` ago (``LINK_LAG`` says why)."""
        name, service = min(self.services.items(), key=lambda item: item[1].robot.scheduler.next_due())
        peers = self._peers.get(name)
        if peers is not None:
            peers.hear(service.robot.scheduler.next_due(), LINK_LAG, HEAR_WAIT)
        token = LOGGING_ROBOT.set(name)
        try:
            service.step()
        finally:
            LOGGING_ROBOT.reset(token)

    def join(self, endpoint: str, tls: Callable[[str], TlsFiles | None], token: str | None) -> None:
        """Each robot's link joins the router at ``endpoint`` under its name (``tls(name)``: its
        certificate; ``token``: the operator token its commands need, None for none)."""
        for name, service in self.services.items():
            self.links.append(LinkServer(service, service.config.link, token, connect=endpoint, tls=tls(name)))
            if self.links[-1].peers is not None:
                self._peers[name] = self.links[-1].peers

    def leave(self, name: str) -> None:
        """Robot ``name``'s link closed and off the fleet (its runtime steps on, unheard)."""
        link = next(k for k in self.links if k.config.robot == name)
        self.links.remove(link)
        self._peers.pop(name, None)
        link.close()

    def close(self) -> None:
        """The links first (no command reaches a runtime being closed), then the runtimes."""
        for link in self.links:
            link.close()
        for service in self.services.values():
            service.close()
        self.scene.close()


def fleet_world(robots: int) -> World:
    """The greenhouse of a fleet sim given no world: the built-in one's 4 pots a row, in as many
    rows as the docks need (one a robot at an aisle's west end, ``sim.generate``), 3 at least."""
    return generate_world(max(3, robots - 1), 4, 1, robots=robots)


def robot_config(config: LupinConfig, name: str, docks: dict | None = None) -> LupinConfig:
    """Robot ``name``'s config: its link name, the fleet's docks (``docks``: the world's spawns,
    unless the config gives them; each robot tells the others where it is from its own,
    ``mission.link.peers``) and, when the config names one, its own state directory inside it
    (two soft-stop latches must never share a file)."""
    update: dict = {"link": {"robot": name}}
    if docks and not config.fleet.docks:
        update["fleet"] = {"docks": docks}
    if config.runtime.state_dir is not None:
        update["runtime"] = {"state_dir": str(Path(config.runtime.state_dir) / name)}
    return with_overrides(config, update)


def start_fleet_sim(world: World, config: LupinConfig, names: list[str], runs: Path, wall_now: Callable[[], float],
                    history: Callable[[str], History | None] = lambda name: None) -> FleetSim:
    """The scene with a robot per name at the world's spawns (in order) and a service on each;
    robot ``name``'s patrols go to ``runs/<name>/`` and into ``history(name)``."""
    scene = SimScene(world, config.sim, names)
    docks = dict(zip(names, spawn_docks(world.spawn_poses).values()))  # robot k at spawn k
    services: dict[str, Service] = {}
    try:
        for k, name in enumerate(names):
            services[name] = start_sim_service(world.for_robot(k), robot_config(config, name, docks), Path(runs) / name,
                                               wall_now, history(name), scene=scene, name=name)
    except BaseException:
        FleetSim(scene, services).close()
        raise
    return FleetSim(scene, services)


def run_fleet(fleet: FleetSim, stop: threading.Event, on_close: Callable[[], None] = lambda: None) -> None:
    """Step ``fleet`` until ``stop`` is set, then close it on this same thread, as one robot's
    service is run (``run_service``: a fleet steps and closes like one). ``on_close`` runs first
    (links made outside ``join``)."""
    run_service(fleet, stop, on_close)
