"""``fleet.sim``: what `lupin fleet sim --robots 3 --fast` costs on ``patrol.large``'s greenhouse.

The 180-pot two-bay world of ``patrol.large`` with a dock for each of 3 robots (``sim.generate``
``robots=3``), its robots idle on their docks as `lupin fleet sim` starts them: one MuJoCo world,
a runtime each in lock-step (``mission.jobs.fleet_sim``), each link joined to a router in the
same process (plain TCP on loopback: the bench measures the fleet, not TLS). Figures:

- ``rtf``: robot seconds per wall second over ``IDLE_S`` of robot time after ``WARMUP_S`` (the
  first SLAM maps made), every robot's clock advancing together; ``rtf_one_robot`` the same for
  a fleet of one on the same world, for scale;
- ``peak_rss_mb``: the high-water resident set of the process (reset at the start where Linux
  allows) plus each robot's SLAM worker's: the whole fleet sim's, an upper bound of its peak at
  any one instant (issue 34's goal: <= 3 GB for 3 robots).

One sample: a fleet's idle run is deterministic for the seed, so repeating it measures only the
machine.
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

from fleet.router import open_router
from lupin.bench import Sample, benchmark
from lupin.bench.meter import _hwm_mb, _reset_hwm
from lupin.bench.patrol import LARGE
from mission.jobs.fleet_sim import FleetSim, start_fleet_sim
from mission.link.session import free_endpoint
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world

ROBOTS = 3
WARMUP_S = 5.0
IDLE_S = 60.0


def _run_to(fleet: FleetSim, t: float) -> None:
    while min(s.now for s in fleet.services.values()) < t:
        fleet.step()


def idle_fleet(robots: int, config: LupinConfig) -> dict:
    """``robots`` robots idle on ``patrol.large``'s docks: rtf and peak memory."""
    rows, per_row, seed, bays = LARGE
    world = generate_world(rows, per_row, seed, bays=bays, robots=ROBOTS)
    endpoint = free_endpoint()
    router = open_router(endpoint, None, None)
    _reset_hwm()
    try:
        with tempfile.TemporaryDirectory() as tmp:
            fleet = start_fleet_sim(world, with_overrides(config, {"sim": {"realtime": False}}),
                                    [f"r{k}" for k in range(1, robots + 1)], Path(tmp), time.perf_counter)
            try:
                fleet.join(endpoint, lambda name: None, None)
                _run_to(fleet, WARMUP_S)
                t0 = time.perf_counter()
                _run_to(fleet, WARMUP_S + IDLE_S)
                wall = time.perf_counter() - t0
                workers = [_hwm_mb(s.nav.localisation.pid) for s in fleet.services.values()]
                main = _hwm_mb()
            finally:
                fleet.close()
    finally:
        router.close()
    return {"rtf": round(IDLE_S / wall, 2), "wall_s": round(wall, 2), "peak_rss_mb": round(main + sum(workers)),
            "process_peak_rss_mb": round(main), "slam_workers_peak_rss_mb": [round(w) for w in workers]}


@benchmark("fleet.sim")
def fleet_sim(config: LupinConfig) -> Sample:
    """3 robots idle in ``patrol.large``'s greenhouse, as fast as the machine allows."""
    three = idle_fleet(ROBOTS, config)
    one = idle_fleet(1, config)
    return Sample([three["wall_s"] * 1000.0], {
        "robots": ROBOTS, "pots": LARGE[0] * LARGE[1] * LARGE[3], "robot_s": IDLE_S, **three,
        "rtf_one_robot": one["rtf"]})
