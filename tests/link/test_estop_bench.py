"""``link.estop`` counts every press: a press that never stops the wheels is a failure, counted
in ``attempted`` and not in ``stopped``, told on stderr and listed; nothing is dropped."""
from __future__ import annotations

from lupin.bench import Sample, summarise
from lupin.bench.link import STOP_WITHIN_S, press_trials


def _run(outcomes, driving=None):
    """``outcomes``: ms per press, None for a press that never stopped the wheels."""
    presses = iter(outcomes)
    driving = iter(driving if driving is not None else [True] * len(outcomes))
    released, told = [], []
    tally = press_trials(len(outcomes), lambda: next(driving), lambda: next(presses),
                         lambda: released.append(True), told.append)
    return tally, released, told


def test_a_press_that_does_not_stop_the_wheels_is_attempted_not_stopped():
    tally, released, told = _run([40.0, None, 60.0])
    assert tally.attempted == 3 and tally.stopped == 2
    assert tally.times_ms == [40.0, 60.0]
    figures = tally.figures()
    assert figures["failed"] == 1 and len(figures["failures"]) == 1 and "trial 2" in figures["failures"][0]
    assert len(released) == 3  # every press is released, the failed one too
    assert any("FAILED" in m and f"{STOP_WITHIN_S:g} s" in m for m in told)


def test_a_trial_not_driving_is_counted_apart_and_pressed_no_more():
    tally, released, told = _run([50.0, None, 55.0], driving=[True, False, True])
    # the second trial is not pressed: the third press outcome (None) is the second press
    assert tally.not_driving == 1 and tally.attempted == 2
    assert tally.stopped == 1 and tally.figures()["failed"] == 1
    assert len(told) == 2


def test_all_presses_failing_still_makes_a_row():
    tally, _, _ = _run([None, None])
    row = summarise("link.estop", Sample(tally.times_ms, tally.figures()))
    assert row["attempted"] == 2 and row["stopped"] == 0 and row["failed"] == 2
    assert row["median_ms"] is None and row["p95_ms"] is None and row["n"] == 0
