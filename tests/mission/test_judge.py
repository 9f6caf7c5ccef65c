"""The scenario judge's e-stop arithmetic on hand-made duty logs (no physics)."""
from __future__ import annotations

import numpy as np
import pytest

from mission.patrol.events_file import parse_events
from mission.runtime.config import LupinConfig
from mission.scenario.judge import MotionLog, estop_figures, presses


def events(*items):
    return parse_events(list(items), "e", LupinConfig())


def test_presses_pair_each_engagement_with_its_release_and_the_resume_after_it():
    found = presses(events({"at": 10.0, "do": "estop", "engaged": True},
                           {"at": 10.0, "do": "soft_estop", "engaged": True},
                           {"at": 12.0, "do": "estop", "engaged": False},
                           {"at": 13.0, "do": "resume"},  # refused: the soft stop still holds
                           {"at": 14.0, "do": "soft_estop", "engaged": False},
                           {"at": 16.0, "do": "resume"},
                           {"at": 20.0, "do": "soft_estop", "engaged": True}), t0=100.0)
    assert [(p.at, p.released, p.resumed) for p in found] == [(110.0, 114.0, 116.0), (120.0, None, None)]


class Log(MotionLog):
    def __init__(self, rows):
        super().__init__(sim=None)
        for t, duty, x in rows:
            self.t.append(t)
            self.duties.append(np.full(4, duty))
            self.xy.append((x, 0.0))


def test_ticks_distance_and_stillness():
    # driving at 0.3 m/s; pressed at 1.0 after that instant's tick; coasts 2 cm; released at 2.0, resumed at 3.0
    rows = [(0.9, 0.5, 0.27), (1.0, 0.5, 0.30), (1.1, 0.0, 0.315), (1.2, 0.0, 0.32), (1.3, 0.0, 0.32),
            (2.0, 0.0, 0.32), (2.5, 0.0, 0.321), (3.0, 0.0, 0.321), (3.1, 0.4, 0.33)]
    [p] = estop_figures(Log(rows), events({"at": 1.0, "do": "estop", "engaged": True},
                                         {"at": 2.0, "do": "estop", "engaged": False},
                                         {"at": 3.0, "do": "resume"}), 0.0, 4.0)
    assert p.ticks_to_zero == 1 and p.distance_after == pytest.approx(0.02)
    assert p.speed == pytest.approx(0.3) and p.still_after_release and p.moved_after_release < 0.002


def test_late_zero_and_motion_before_resume_are_caught():
    rows = [(1.0, 0.5, 0.0), (1.1, 0.5, 0.03), (1.2, 0.0, 0.05), (2.0, 0.0, 0.05), (2.2, 0.3, 0.06), (2.4, 0.0, 0.08)]
    [p] = estop_figures(Log(rows), events({"at": 1.0, "do": "estop", "engaged": True},
                                         {"at": 2.0, "do": "estop", "engaged": False}), 0.0, 3.0)
    assert p.ticks_to_zero == 2
    assert not p.still_after_release and p.moved_after_release == pytest.approx(0.03)
