"""Pot approaches in generated greenhouses: the navigation stack's acceptance trial.

Each trial world is ``lupin sim generate`` output (3 rows x 5 pots, seeded); the robot starts at
the spawn and visits a seeded random choice of pots in turn, as a patrol would, navigating to
each pot's approach pose (spec/mission.md: ``standoff`` 0.5 m out along the pot's ``facing``,
heading ``facing + pi``, i.e. looking at the tag).

An approach is judged on ground truth (``Approach.succeeded``): the navigator reported arrival
within its timeout (without that the patrol would not inspect the pot) *and* the robot truly
stands within the goal checker's tolerance of the approach pose (0.25 m / 0.12 rad; the truth
pose is the sim's, read only to judge, never to steer), so the pot is inspected from where it
should be. The navigator's own verdict and its belief's error are kept beside it
(``outcome``, ``map_error``), so a false arrival shows. Every contact of the chassis counts
(``mission.jobs.contacts``), not only the first with each body.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Callable, Optional

from mission.approach import approach_pose
from mission.jobs.navigate import start_navigate
from mission.runtime.config import LupinConfig, with_seed
from nav.frames import distance, yaw_error
from sim.generate import generate_world

ROWS, POTS_PER_ROW = 3, 5
TIMEOUT_S = 60.0


@dataclass(frozen=True)
class Approach:
    world_seed: int
    pot: str
    outcome: str
    """The navigator's verdict (succeeded / failed / canceled): the robot's own belief."""
    reason: str
    sim_time_s: float
    map_error: tuple[float, float]
    """(xy m, yaw rad) of the navigator's own pose estimate against the goal at the end."""
    truth_error: tuple[float, float]
    """(xy m, yaw rad) of ground truth against the goal at the end."""
    bumped: bool
    """The chassis touched something during this approach."""
    contacts: int = 0
    """Contacts that began during this approach (each touch counts, the same body again too)."""
    wall_s: Optional[float] = None
    """Wall seconds of this approach alone, when the caller gave a wall clock (benchmarks)."""
    tolerance: tuple[float, float] = (0.25, 0.12)
    """(xy m, yaw rad) the truth is judged against: the goal checker's."""

    @property
    def truth_within(self) -> bool:
        """Ground truth ends within the tolerance of the approach pose."""
        return self.truth_error[0] <= self.tolerance[0] and self.truth_error[1] <= self.tolerance[1]

    @property
    def succeeded(self) -> bool:
        """The pot is inspected from within tolerance: the navigator arrived, and truly so."""
        return self.outcome == "succeeded" and self.truth_within


def run_world(config: LupinConfig, world_seed: int, pots: int,
              wall: Callable[[], float] | None = None) -> list[Approach]:
    """Visit ``pots`` seeded random pots of one generated greenhouse in turn; ``wall`` (a wall
    clock, seconds) times each approach when given."""
    world = generate_world(ROWS, POTS_PER_ROW, world_seed)
    chosen = random.Random(world_seed).sample(world.pots, pots)
    run = start_navigate(world, with_seed(config, world_seed))
    checker = config.nav.goal_checker
    out = []
    try:
        for pot in chosen:
            goal = approach_pose(pot.x, pot.y, pot.facing)
            t0 = run.now
            w0 = wall() if wall is not None else None
            outcome = run.go(goal, TIMEOUT_S)
            w1 = wall() if wall is not None else None
            belief = run.nav.map_pose()
            target = run.to_map(goal)
            touches = run.contacts.since(t0)
            out.append(Approach(world_seed, pot.id, outcome, run.nav.reason, run.now - t0,
                                (distance(belief, target), yaw_error(belief, target)),
                                run.truth_error(goal), bool(touches), len(touches),
                                None if wall is None else w1 - w0,
                                (checker.xy_tolerance, checker.yaw_tolerance)))
    finally:
        run.close()
    return out


def run_trials(config: LupinConfig, worlds: int = 10, pots_per_world: int = 5, first_seed: int = 1,
               wall: Callable[[], float] | None = None) -> list[Approach]:
    """``worlds * pots_per_world`` approaches (50 by default, the issue's trial)."""
    results: list[Approach] = []
    for seed in range(first_seed, first_seed + worlds):
        results += run_world(config, seed, pots_per_world, wall)
    return results
