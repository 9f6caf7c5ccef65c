"""Each event's effect, judged on hand-made motion logs (no physics): a run where the event did
its job passes, and the same run with an event that did nothing fails, saying what happened."""
from __future__ import annotations

import numpy as np
import pytest

from mission.patrol.events_file import parse_events
from mission.runtime.config import LupinConfig
from mission.scenario.checks import effects
from mission.scenario.effects import event_effects
from mission.scenario.motion_log import MotionLog
from mission.scenario.scenario_file import EffectsExpect

TICKS = np.round(np.arange(0.0, 8.0, 0.1), 3)
DRIVE = (0.3, 0.0, 0.0)
STILL = (0.0, 0.0, 0.0)


def judge(script: list[dict], rows, expect: dict) -> tuple:
    """Every event fired when scripted; ``rows(t)`` -> (duty, (x, y, yaw), command, source, known,
    workers) per control tick. Returns the checks and the events' figures."""
    events = parse_events(script, "e", LupinConfig())
    log = MotionLog(sim=None, dead_zone=0.1)
    for t in TICKS:
        duty, pose, command, source, known, workers = rows(t)
        log.add(float(t), [duty] * 4, pose, command, source, known, workers)
    found = event_effects(log, events, {i: e.at for i, e in enumerate(events)}, float(TICKS[-1]),
                          EffectsExpect.model_validate(expect))
    return effects(EffectsExpect.model_validate(expect), found, 0.0), [v.figures for v in found]


def driving(t: float, until: float = 99.0, x0: float = 0.0):
    """Autonomy at 0.3 m/s along x (0.03 m a tick) up to ``until``, then standing there."""
    x = x0 + 0.3 * min(t, until)
    return (0.4, (x, 0.0, 0.0), DRIVE, "auto", 1000, 1) if t <= until else (0.015, (x, 0.0, 0.0), STILL, "idle", 1000, 1)


# --- pause: the base is held still until the resume -----------------------------------------

PAUSE = [{"at": 2.0, "do": "pause"}, {"at": 5.0, "do": "resume"}]


def paused(t: float):
    if t <= 2.0:
        return driving(t)
    if t > 5.0:
        return driving(t - 5.0, x0=0.632)
    if t <= 2.1:  # the brake tick: a duty past the dead zone, the base still coasting
        return -0.3, (0.63, 0.0, 0.0), STILL, "idle", 1000, 1
    return 0.015, (0.632, 0.0, 0.0), STILL, "idle", 1000, 1  # the PID's residue: inside the dead zone


def test_a_pause_that_holds_the_base_passes():
    [check], [figures, _] = judge(PAUSE, paused, {"pause": {"still_within": 1.0}})
    assert check.passed, check.line()
    assert figures["held_after_s"] == pytest.approx(0.2) and figures["moved_m"] == 0.0
    assert figures["max_duty_while_held"] == 0.015


def test_a_pause_that_did_nothing_fails():
    [check], _ = judge(PAUSE, driving, {"pause": {}})
    assert not check.passed
    assert "the wheels were driven until 5.0 s (the pause held nothing)" in check.actual
    assert "moved 600.0 mm from 3.0 s to 5.0 s" in check.actual


def test_a_pause_that_creeps_fails():
    def creeping(t):
        duty, (x, y, yaw), *rest = paused(t)
        return (duty, (x + 0.003 * max(t - 2.0, 0.0) * (t <= 5.0), y, yaw), *rest)

    [check], _ = judge(PAUSE, creeping, {"pause": {"max_motion": 0.005}})
    assert not check.passed and "moved 6.0 mm" in check.actual


# --- lidar dropout: zero twist while blind, autonomy drives after -----------------------------

DROPOUT = [{"at": 2.0, "do": "lidar_dropout", "duration": 2.0}]


def blind(t: float):
    if 2.0 < t <= 4.0:
        return 0.015, (0.62, 0.0, 0.0), STILL, "auto", 1000, 1
    return driving(t - 4.0, x0=0.62) if t > 4.0 else driving(t)


def test_a_dropout_that_holds_the_twist_passes():
    [check], [figures] = judge(DROPOUT, blind, {"lidar_dropout": {"zero_twist_within": 0.3, "drives_again_within": 0.5}})
    assert check.passed, check.line()
    assert figures["zero_twist_after_s"] == pytest.approx(0.1) and figures["drives_again_after_s"] == pytest.approx(0.1)


def test_a_dropout_that_did_nothing_fails():
    [check], _ = judge(DROPOUT, driving, {"lidar_dropout": {}})
    assert not check.passed and check.actual.startswith("the base was driven until the scans came back")


def test_a_patrol_that_stays_stopped_after_the_dropout_fails():
    [check], _ = judge(DROPOUT, lambda t: driving(t, until=2.0), {"lidar_dropout": {}})
    assert not check.passed and check.actual.endswith("autonomy never drove again")


# --- clear_map: erased, respawned, back --------------------------------------------------------

RESET = [{"at": 2.0, "do": "clear_map"}]


def reset(t: float):
    duty, pose, command, source, _, _ = driving(t)
    if t <= 2.0:
        return duty, pose, command, source, 1000, 1
    known = 0 if t < 3.0 else min(1000, int(200 + 300 * (t - 3.0)))  # a fresh worker from 3.0
    return duty, pose, command, source, known, 1 if t < 3.0 else 2


def test_a_reset_whose_map_comes_back_passes():
    [check], [figures] = judge(RESET, reset, {"clear_map": {"map_back": 0.8, "within": 5.0}})
    assert check.passed, check.line()
    assert figures["known_before"] == 1000 and figures["erased"] and figures["respawned"]
    assert figures["back_after_s"] == pytest.approx(3.0)  # 200 + 300 * 2.0 = 800 at 5.0


def test_a_reset_that_did_nothing_fails():
    [check], _ = judge(RESET, driving, {"clear_map": {}})
    assert not check.passed and check.actual.startswith("never erased, no new worker")


def test_a_map_that_does_not_come_back_in_time_fails():
    [check], _ = judge(RESET, reset, {"clear_map": {"map_back": 0.8, "within": 2.5}})
    assert not check.passed and check.actual == "erased, respawned, 650 cells known 2.5 s after"


# --- teleop: the source takes the wheels, the base follows the stick ---------------------------

JOY = [{"at": 2.0, "do": "teleop", "source": "joy", "vx": 0.0, "vy": 0.0, "wz": 0.6, "duration": 1.0}]


def joy(t: float):
    if 2.0 < t <= 3.3:  # held to 3.0, live in the mux for 0.3 s after: turning on the spot
        return 0.3, (0.6, 0.0, 0.6 * (t - 2.0)), (0.0, 0.0, 0.6), "joy", 1000, 1
    return driving(t - 3.3, x0=0.6) if t > 3.3 else driving(t)


def test_a_gamepad_that_takes_the_wheels_passes():
    [check], [figures] = judge(JOY, joy, {"teleop": {"settle": 0.5, "tolerance": 0.05}})
    assert check.passed, check.line()
    assert figures["ticks_owned"] == figures["ticks"] == 10
    assert figures["true_twist"] == pytest.approx([0.0, 0.0, 0.6], abs=1e-6)


def test_a_gamepad_that_did_nothing_fails():
    [check], _ = judge(JOY, driving, {"teleop": {}})
    assert not check.passed
    assert check.actual == "0 of 10 ticks followed the stick, first not at 2.1 s (auto); true twist (0.30, 0.00, 0.00)"


def test_a_gamepad_held_off_by_the_estop_fails():
    def stopped(t):
        row = joy(t)
        return (0.0, (0.6, 0.0, 0.0), STILL, "estop", 1000, 1) if 2.0 < t <= 3.3 else row

    [check], _ = judge(JOY, stopped, {"teleop": {}})
    assert not check.passed and "first not at 2.1 s (estop)" in check.actual


def test_an_expected_effect_without_its_event_fails():
    [check], _ = judge(PAUSE, paused, {"clear_map": {}})
    assert not check.passed and check.actual == "no clear_map in the events"
