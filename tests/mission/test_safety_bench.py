"""safety.people's bookkeeping: held-out worlds and each patrol's own figures (the patrols
themselves are the benchmark's, too long for a test)."""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

import lupin.bench.safety as bench
from hw.errors import InputError
from lupin.bench.safety import (ENCOUNTERS_ENV, MAX_WORLDS, MIN_ENCOUNTERS, MIN_PATROLS, TRACED_SEEDS, _each,
                                _wanted, eval_seeds)
from mission.runtime.config import LupinConfig
from sim.generate import generate_world


@pytest.mark.parametrize("sim_seed", [0, 1, 7])
def test_the_worlds_scored_are_never_the_ones_the_rules_were_traced_on(sim_seed):
    seeds = list(eval_seeds(sim_seed))
    assert len(seeds) == len(set(seeds)) == MAX_WORLDS
    assert not set(seeds) & set(TRACED_SEEDS)
    assert list(eval_seeds(sim_seed)) == seeds  # the same run, the same worlds


def test_each_patrol_reports_its_own_figures_and_no_clearance_when_it_never_passed_anyone_moving():
    world = generate_world(2, 2, 101, walkers=1)
    log = SimpleNamespace(encounters=[{}, {}, {}], moving_contacts=[(1.0, "walker_W1")], clearance=0.1234,
                          contacts=SimpleNamespace(onsets=[(1.0, "walker_W1"), (9.0, "walker_W1")]))
    row = _each(101, world, {"outcome": "completed", "sim_time_s": 321.5}, log, 3, 120.0)
    assert row == {"seed": 101, "encounters": 3, "contacts_while_moving": 1, "contacts_standing_or_moving": 2,
                   "min_clearance_while_moving_m": 0.123, "correct": 3, "pots": 4, "outcome": "completed",
                   "robot_time_s": 321.5, "empty_robot_time_s": 120.0}
    log.clearance = math.inf
    assert _each(101, world, {"outcome": "completed", "sim_time_s": 1.0}, log, 0, 1.0)["min_clearance_while_moving_m"] is None


def test_the_figure_needs_three_patrols_and_a_quick_look_only_its_encounters(monkeypatch):
    monkeypatch.delenv(ENCOUNTERS_ENV, raising=False)
    assert _wanted() == (MIN_ENCOUNTERS, MIN_PATROLS) and MIN_PATROLS >= 3
    monkeypatch.setenv(ENCOUNTERS_ENV, "30")
    assert _wanted() == (30, 1)
    monkeypatch.setenv(ENCOUNTERS_ENV, "thirty")
    with pytest.raises(InputError, match=ENCOUNTERS_ENV):
        _wanted()


def test_the_runs_figures_are_its_patrols_summed(monkeypatch):
    """The patrols stood in for (each takes minutes): the run's contacts, clearance, success and
    times are those of its patrols, and it stops at the third once the encounters are in."""
    least = iter([0.31, 0.27, 0.35, 0.2])  # each patrol with people's least while moving; a fourth is never run

    def patrol(world, config):
        walkers = bool(world.walkers)
        log = SimpleNamespace(encounters=[{"walker": "W1", "nearest_moving_m": 0.4, "moving_at": None, "lost_s": 1.0}] * 100,
                              moving_contacts=[], clearance=next(least) if walkers else math.inf,
                              contacts=SimpleNamespace(onsets=[(1.0, "walker_W1")]))
        return {"outcome": "completed", "sim_time_s": 900.0 if walkers else 400.0}, log

    monkeypatch.delenv(ENCOUNTERS_ENV, raising=False)
    monkeypatch.setattr(bench, "_patrol", patrol)
    monkeypatch.setattr(bench, "correct_pots", lambda world, doc: len(world.pots) - 1)
    monkeypatch.setattr(bench, "_wrong", lambda world, doc: [])
    out = bench.people(LupinConfig()).figures
    assert out["patrols"] == MIN_PATROLS == len(out["patrols_each"]) and out["encounters"] == 100 * MIN_PATROLS
    assert [e["seed"] for e in out["patrols_each"]] == list(eval_seeds(0))[:MIN_PATROLS]
    assert out["contacts_while_moving"] == 0 and out["contacts_standing_or_moving"] == MIN_PATROLS
    assert [e["min_clearance_while_moving_m"] for e in out["patrols_each"]] == [0.31, 0.27, 0.35]
    assert out["min_clearance_while_moving_m"] == 0.27
    assert out["success_rate"] == round(47 / 48, 4) and len(out["patrols_not_all_correct"]) == MIN_PATROLS
    assert out["patrol_time_median_s"] == 900.0 and out["extra_time_per_patrol_median_s"] == 500.0
