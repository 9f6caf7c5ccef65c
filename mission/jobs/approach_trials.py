"""Pot approaches in generated greenhouses: the navigation stack's acceptance trial.

Each trial world is ``lupin sim generate`` output (3 rows x 5 pots, seeded); the robot starts at
the spawn and visits a seeded random choice of pots in turn, as a patrol would, navigating to
each pot's approach pose (spec/mission.md: ``standoff`` 0.5 m out along the pot's ``facing``,
heading ``facing + pi``, i.e. looking at the tag). An approach succeeds when the navigator
reports success (its goal checker: 0.25 m / 0.12 rad in the map frame) within its timeout;
ground truth is recorded beside it, for judging localisation, never for steering.
"""
from __future__ import annotations

import random
from dataclasses import dataclass

from mission.runtime.config import LupinConfig, with_seed
from mission.approach import approach_pose
from mission.jobs.navigate import start_navigate
from nav.frames import distance, yaw_error
from sim.generate import generate_world

ROWS, POTS_PER_ROW = 3, 5
TIMEOUT_S = 60.0


@dataclass(frozen=True)
class Approach:
    world_seed: int
    pot: str
    outcome: str
    reason: str
    sim_time_s: float
    map_error: tuple[float, float]
    """(xy m, yaw rad) of the navigator's own pose estimate against the goal at the end."""
    truth_error: tuple[float, float]
    """(xy m, yaw rad) of ground truth against the goal at the end."""
    bumped: bool


def run_world(config: LupinConfig, world_seed: int, pots: int) -> list[Approach]:
    """Visit ``pots`` seeded random pots of one generated greenhouse in turn."""
    world = generate_world(ROWS, POTS_PER_ROW, world_seed)
    chosen = random.Random(world_seed).sample(world.pots, pots)
    run = start_navigate(world, with_seed(config, world_seed))
    out = []
    try:
        for pot in chosen:
            goal = approach_pose(pot.x, pot.y, pot.facing)
            t0, bumps = run.now, len(run.bumps)
            outcome = run.go(goal, TIMEOUT_S)
            belief = run.nav.map_pose()
            target = run.to_map(goal)
            out.append(Approach(world_seed, pot.id, outcome, run.nav.reason, run.now - t0,
                                (distance(belief, target), yaw_error(belief, target)),
                                run.truth_error(goal), len(run.bumps) > bumps))
    finally:
        run.close()
    return out


def run_trials(config: LupinConfig, worlds: int = 10, pots_per_world: int = 5, first_seed: int = 1) -> list[Approach]:
    """``worlds * pots_per_world`` approaches (50 by default, the issue's trial)."""
    results: list[Approach] = []
    for seed in range(first_seed, first_seed + worlds):
        results += run_world(config, seed, pots_per_world)
    return results
