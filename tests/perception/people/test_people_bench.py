"""``perception.people`` (lupin/bench/people.py) on one tuning world: the runtime's people tick
on sim-rendered scans finds the standing, crouching and cart-pushing workers by the path, and
the people the rules act on are people (hardly a crate or a pot among them), judged on ground truth."""
from __future__ import annotations

import pytest

from lupin.bench.people import MAP_EVERY, TUNING_SEEDS, path_poses, run_world
from mission.runtime.config import LupinConfig


@pytest.mark.slow
def test_one_world_of_the_bench_finds_the_workers_and_acts_on_people_only():
    r = run_world(TUNING_SEEDS[0], LupinConfig())
    scans = len(path_poses())  # one tick timed per scan, those that took in a new map apart
    assert len(r["times"]) + len(r["intake_times"]) == scans and len(r["intake_times"]) == -(-scans // MAP_EVERY)
    assert r["wanted"] > 100 and r["found"] / r["wanted"] >= 0.95
    assert set(r["by_posture"]) >= {"standing", "crouching"}
    assert r["acted_reported"] > 0 and r["acted_right"] / r["acted_reported"] >= 0.95  # issue 28: precision >= 0.9
    assert r["acted_found"] / r["wanted"] >= 0.8
