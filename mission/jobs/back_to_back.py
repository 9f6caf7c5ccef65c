"""Patrols back to back on one running service, as `lupin serve` runs them all day: after each,
what the process holds (resident memory, threads, SLAM workers), the map and the report.

A robot that runs for a season must not grow with every patrol: the service keeps one runtime,
one SLAM worker and one map across patrols, and each patrol's tree, camera pipelines and report
are let go when it ends. ``lupin bench serve.back_to_back`` and a slow test read this.
"""
from __future__ import annotations

import json
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from mission.jobs.serve import Service
from mission.jobs.sim_serve import start_sim_service
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig
from nav.slam.supervisor import SlamSupervisor
from sim.world import load_default_world


@dataclass(frozen=True)
class AfterPatrol:
    outcome: str
    inspected: int
    report: Path
    rss_mb: float
    threads: int
    slam_workers: int
    """SLAM worker processes this service has alive (1 while mapping)."""
    map_cells_known: int


def rss_mb() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return 0.0


def run_patrols(service: Service, mission: dict, count: int, limit_s: float = 1200.0) -> list[AfterPatrol]:
    """Start ``mission`` (spec/mission.md, as a link command carries it) ``count`` times, each
    when the last has ended, stepping the service; what is held after each."""
    out = []
    for _ in range(count):
        service.mission_start(mission)
        run = service.run
        deadline = service.now + limit_s
        while service.run is not None and service.now < deadline:
            service.step()
        if service.run is not None:
            service.mission_abort()
        doc = json.loads(run.report.path.read_text())
        slam = service.nav.localisation
        alive = int(isinstance(slam, SlamSupervisor) and slam.pid is not None)
        occupancy = slam.occupancy if isinstance(slam, SlamSupervisor) else None
        out.append(AfterPatrol(doc["outcome"], sum(p["status"] == "inspected" for p in doc["pots"]), run.report.path,
                               rss_mb(), threading.active_count(), alive,
                               int((occupancy.occupancy >= 0).sum()) if occupancy is not None else 0))
    return out


def default_world_patrols(config: LupinConfig, runs: Path, pots: int, count: int,
                          clock: Callable[[], float]) -> list[AfterPatrol]:
    """The built-in greenhouse's first ``pots`` pots patrolled ``count`` times on one fresh sim
    service (``clock``: its wall clock), reports under ``runs``; what is held after each."""
    world = load_default_world()
    mission = mission_from_world(world)
    mission = mission.model_copy(update={"name": "b2b", "pots": mission.pots[:pots]}).model_dump(mode="json")
    service = start_sim_service(world, config, runs, clock)
    try:
        return run_patrols(service, mission, count)
    finally:
        service.close()
