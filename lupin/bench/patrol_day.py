"""``patrol.day``: a day's patrol longer than one battery (issue 31), as `lupin patrol` runs it.

A generated two-bay greenhouse of 432 pots over 60 m (8 rows of 27 pots a bay, seed 31: a
world nothing was tuned on), every pot, the sim's real 2.2 Ah pack, charging on the dock
between legs; ``patrol.day_long`` the same over 480 pots and 66 m (seed 37), which the pack
does not cover in one charge. The figures: pots right (inspected with the world's tag, colour and pest), the
legs and charges, robot time out on legs and on the dock charging, the lowest charge the pack
reached (the sim's true charge, goal: never below the reserve; and the robot's own estimate),
turn-offs (the power policy's, goal 0), wall time and the runtime's peak memory (goal <= 1.5 GB
for the whole day).
"""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

from lupin.bench import Sample, benchmark
from lupin.bench.meter import PatrolMeter
from lupin.bench.patrol import correct_pots
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig
from sim.generate import generate_world

DAY = (8, 27, 31, 2)
"""rows, pots per row, seed, bays: 432 pots, a 60 x 9 m floor."""
LONG_DAY = (8, 30, 37, 2)
"""``patrol.day_long``: 480 pots on a 66 x 9 m floor, more than the pack does in one charge."""


@benchmark("patrol.day")
def day(config: LupinConfig) -> Sample:
    return whole_day(config, *DAY)


@benchmark("patrol.day_long")
def day_long(config: LupinConfig) -> Sample:
    return whole_day(config, *LONG_DAY)


def whole_day(config: LupinConfig, rows: int, per_row: int, seed: int, bays: int) -> Sample:
    """Every pot of a generated greenhouse, across as many charges as it takes."""
    world = generate_world(rows, per_row, seed, bays=bays)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        run = start_sim_patrol(world, mission_from_world(world), config, Path(tmp) / "report.json", time.perf_counter)
        meter, pack, power = PatrolMeter(run), run.sim.sim.battery, run.robot.power
        lowest, turn_offs, off = pack.charge, 0, False
        try:
            while not run.done:
                run.step()
                lowest = min(lowest, pack.charge)
                turn_offs += power.state.turn_off and not off
                off = power.state.turn_off
            doc = run.finish(run.outcome())
            cost = meter.figures()
        finally:
            run.close()
        wall = time.perf_counter() - t0
    legs = doc["legs"]
    out_s = sum((g["returned_s"] or doc["sim_time_s"]) - g["left_s"] for g in legs)
    charging_s = sum(g["charged_s"] - g["returned_s"] for g in legs if g.get("charged_s") is not None)
    return Sample([wall * 1000.0], {
        "pots": len(world.pots), "floor_m": [world.floor.x, world.floor.y], "outcome": doc["outcome"],
        "inspected": sum(p["status"] == "inspected" for p in doc["pots"]), "pots_right": correct_pots(world, doc),
        "legs": len(legs), "charges": doc["energy"]["charges"], "robot_time_s": doc["sim_time_s"],
        "out_on_legs_s": round(out_s, 1), "charging_s": round(charging_s, 1),
        "lowest_charge": round(lowest, 4), "lowest_charge_estimated": doc["energy"]["lowest_charge"],
        "reserve": doc["energy"]["reserve"], "turn_offs": turn_offs, "distance_m": doc["distance_m"],
        "why_home": [g.get("why_home", "") for g in legs], "energy_model": doc["energy"],
        "wall_time_s": round(wall, 1), "peak_rss_mb": cost["peak_rss_mb"],
        "slam_worker_peak_rss_mb": cost["slam_worker_peak_rss_mb"]})
