"""The rate scheduler on the sim clock: rates, ordering, exact times, determinism."""
import pytest

from sim.clock import SimClock
from mission.runtime.scheduler import Scheduler


def test_tasks_run_at_their_rates_in_registration_order():
    advanced = []
    clock = SimClock(advance=advanced.append)
    s = Scheduler(clock)
    log = []
    s.every("ctrl", 10.0, lambda t: log.append(("ctrl", t)))
    s.every("estop", 5.0, lambda t: log.append(("estop", t)))
    s.run_until(1.0)
    ctrl = [t for n, t in log if n == "ctrl"]
    estop = [t for n, t in log if n == "estop"]
    assert len(ctrl) == 11 and len(estop) == 6
    assert ctrl[3] == pytest.approx(0.3, abs=1e-12)
    # at shared instants, the earlier-registered task runs first
    assert log[0] == ("ctrl", 0.0) and log[1] == ("estop", 0.0)
    # the clock was advanced only to instants where something was due, then to the end
    assert advanced[-1] == 1.0 and clock.now() == 1.0
    assert all(b > a for a, b in zip(advanced, advanced[1:]))


def test_no_drift_over_a_long_run():
    clock = SimClock()
    s = Scheduler(clock)
    ticks = []
    s.every("ctrl", 10.0, ticks.append)
    s.run_until(3600.0)
    assert len(ticks) == 36001
    assert ticks[-1] == 3600.0


def test_cancel_and_bad_rates():
    s = Scheduler(SimClock())
    hits = []
    s.every("a", 10.0, hits.append)
    with pytest.raises(ValueError):
        s.every("a", 10.0, hits.append)
    with pytest.raises(ValueError):
        s.every("b", 0.0, hits.append)
    s.run_until(0.25)
    s.cancel("a")
    s.every("c", 1.0, lambda t: None)
    s.run_until(2.0)
    assert len(hits) == 3


def test_a_task_can_cancel_itself():
    s = Scheduler(SimClock())
    hits = []

    def once(t):
        hits.append(t)
        s.cancel("once")

    s.every("once", 10.0, once)
    s.every("keep", 1.0, lambda t: None)
    s.run_until(1.0)
    assert hits == [0.0]


def test_one_shot_tasks_run_once_at_their_instant_after_earlier_registered_tasks():
    s = Scheduler(SimClock())
    log = []
    s.every("ctrl", 10.0, lambda t: log.append(("ctrl", t)))
    s.at("press", 0.3, lambda t: log.append(("press", t)))
    s.at("late", 0.05, lambda t: log.append(("late", t)))
    s.run_until(1.0)
    assert [e for e in log if e[0] != "ctrl"] == [("late", 0.05), ("press", 0.3)]
    assert log.index(("ctrl", 0.3)) + 1 == log.index(("press", 0.3))  # same instant: registration order
    assert "press" not in s.tasks and "late" not in s.tasks
    s.at("press", 0.5, lambda t: log.append(("again", t)))  # in the past: runs now, name reusable
    s.run_until(1.05)
    assert ("again", 1.0) in log
