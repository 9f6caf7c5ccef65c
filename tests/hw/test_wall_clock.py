"""The hardware clock: monotonic, and waiting reaches the requested instant (never early)."""
import pytest

from hw.interfaces import Clock, Twist
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


def test_wall_pace_holds_a_clock_back_to_wall_time(monkeypatch):
    from hw import wall_clock

    wall, slept = {"t": 50.0}, []
    monkeypatch.setattr(wall_clock.time, "monotonic", lambda: wall["t"])
    monkeypatch.setattr(wall_clock.time, "sleep", lambda s: slept.append(round(s, 6)))
    pace = wall_clock.WallPace(start=10.0)
    pace.wait(10.5)  # 0.5 s of sim time at once: wait 0.5 s of wall time
    wall["t"] = 51.0  # a slow step: the sim is now behind the wall
    pace.wait(10.6)
    assert slept == [0.5]


@pytest.mark.slow
def test_a_realtime_sim_waits_on_the_wall_before_each_step_and_runs_the_same_trajectory(monkeypatch):
    from sim import scene
    from tests.fixtures import assemble, open_floor

    waits = []

    class Recording(scene.WallPace):
        def wait(self, t):
            waits.append(t)  # the pacing itself is the test above; here: is it asked, in order?

    monkeypatch.setattr(scene, "WallPace", Recording)  # the scene paces the engine all robots share

    def drive(**env):
        sim, robot = assemble(open_floor(), **env)
        robot.mux.publish("manual", Twist(0.2, 0.1, 0.3), 0.0)
        robot.scheduler.run_for(0.3)
        pose = sim.truth()
        sim.close()
        return pose

    assert drive() is not None and waits == []
    paced = drive(LUPIN_SIM__REALTIME="true")
    assert len(waits) >= 3 and waits == sorted(waits) and waits[-1] == 0.3
    assert paced == drive()
