"""The sim's ``lidar_blind`` fault through the whole base chain: the scans keep arriving on time
with every return invalid, the collision monitor calls them blind on the tick the first one
arrives and the base gets no linear twist, and it drives again on the tick the lidar sees."""
from __future__ import annotations

import numpy as np

import pytest

from hw.interfaces import Twist
from tests.fixtures import assemble, open_floor

pytestmark = pytest.mark.slow


def test_lidar_blind_stops_the_base_on_the_tick_its_first_blind_scan_arrives():
    sim, robot = assemble(open_floor(spawn=(4.0, 3.0, 0.0)))
    try:
        sched, t = robot.scheduler, 0.0
        drive = Twist(0.35, 0.0, 0.0)
        while robot.base.odometry.twist.vx < 0.3:  # up to speed on the operator's source
            t = round(t + 0.1, 6)
            robot.mux.publish("manual", drive, t)
            sched.run_until(t)
        t = round(t + 0.05, 6)  # between two ticks and two revolutions
        sched.run_until(t)
        sim.faults.lidar_blind(1.0)
        start = t
        scans = []
        for _ in range(3):
            t = round(t + 0.05, 6)
            robot.mux.publish("manual", drive, t)
            sched.run_until(t)
            scans.append((robot.hal.lidar.latest_scan(), robot.base.command))
        first_blind = next(i for i, (s, _) in enumerate(scans) if s.stamp > start)
        assert not np.isfinite(scans[first_blind][0].ranges).any()  # on time, every return invalid
        assert robot.monitor.fault == "lidar_blind" and robot.monitor.untrusted_since > start
        # the base tick that took the first blind revolution handed the wheels no linear twist
        tick = robot.monitor.untrusted_since
        assert robot.base.command.vx == 0.0 and tick - start <= 0.1 + 1e-9
        while t < start + 1.0:
            t = round(t + 0.1, 6)
            robot.mux.publish("manual", drive, t)
            sched.run_until(t)
            if t < start + 1.0 - 1e-9:
                assert robot.base.command.vx == 0.0
        t = round(t + 0.1, 6)
        robot.mux.publish("manual", drive, t)
        sched.run_until(t)
        assert robot.monitor.fault is None and robot.base.command.vx == pytest.approx(0.35)
    finally:
        sim.close()
        robot.close()
