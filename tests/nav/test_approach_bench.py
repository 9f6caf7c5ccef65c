"""``nav.approach`` judges on ground truth, times each approach and counts every contact: an
arrival the truth does not bear out is a failure, and touching the same body twice is two
contacts."""
from __future__ import annotations

import time

import pytest

from lupin.bench import Sample, summarise
from lupin.bench.nav_approach import figures
from mission.jobs.approach_trials import Approach, run_world
from mission.jobs.contacts import ContactLog
from mission.runtime.config import load_config


def _approach(outcome="succeeded", truth=(0.05, 0.02), contacts=0, wall_s=1.0, pot="P01"):
    return Approach(1, pot, outcome, "" if outcome == "succeeded" else "timeout", 9.0, (0.04, 0.02), truth,
                    contacts > 0, contacts, wall_s)


def test_an_arrival_outside_the_tolerance_by_truth_is_a_failure():
    results = [_approach(), _approach(truth=(0.31, 0.02), pot="P02"), _approach(truth=(0.1, 0.2), pot="P03"),
               _approach("failed", truth=(0.1, 0.01), pot="P04")]
    f = figures(results)
    assert f["navigator_succeeded"] == 3 and f["succeeded"] == 1
    assert f["false_arrivals"] == 2
    assert len(f["failures"]) == 3 and any("P02" in m and "truth" in m for m in f["failures"])
    assert f["worst_truth_xy_m"] == 0.05  # of the true successes only


def test_every_contact_counts():
    f = figures([_approach(contacts=3), _approach(contacts=0, pot="P02"), _approach(contacts=1, pot="P03")])
    assert f["contacts"] == 4 and f["bumps"] == 2


def test_times_are_per_approach():
    results = [_approach(wall_s=s, pot=f"P{i}") for i, s in enumerate([1.0, 2.0, 3.0, 4.0, 40.0])]
    row = summarise("nav.approach", Sample([r.wall_s * 1000 for r in results], figures(results)))
    assert row["n"] == 5 and row["median_ms"] == 3000.0 and row["p95_ms"] > 4000.0


def test_the_contact_log_counts_each_onset_the_same_body_again_too():
    frames = iter([[], ["pot_P01"], ["pot_P01"], [], ["pot_P01", "wall_n"], ["wall_n"], []])
    log = ContactLog(lambda: next(frames))
    for i in range(7):
        log.pre_chunk(i * 0.01)
    assert [name for _, name in log.onsets] == ["pot_P01", "pot_P01", "wall_n"]
    assert len(log.since(0.035)) == 2


@pytest.mark.slow
def test_a_trial_world_times_and_judges_each_approach():
    results = run_world(load_config(env={}), 3, 2, wall=time.perf_counter)
    assert len(results) == 2
    for r in results:
        assert r.wall_s is not None and r.wall_s > 0
        assert r.succeeded == (r.outcome == "succeeded" and r.truth_error[0] <= 0.25 and r.truth_error[1] <= 0.12)
        assert r.contacts == 0 and not r.bumped
