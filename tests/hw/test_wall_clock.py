"""The hardware clock: monotonic, and waiting reaches the requested instant (never early)."""
from hw.interfaces import Clock
from hw.wall_clock import WallClock


def test_wall_clock_is_a_clock_that_never_returns_early():
    clock = WallClock()
    assert isinstance(clock, Clock)
    t0 = clock.now()
    target = t0 + 0.02
    clock.wait_until(target)
    assert clock.now() >= target
    clock.wait_until(t0)  # the past: returns at once, time does not go backwards
    assert clock.now() >= target
