"""The scenario judge's e-stop arithmetic on hand-made motion logs (no physics), with the events
as they fired."""
from __future__ import annotations

import pytest

from mission.patrol.events_file import parse_events
from mission.runtime.config import LupinConfig
from mission.scenario.checks import estop, expectations, Ending
from mission.scenario.effects import event_effects
from mission.scenario.judge import estop_figures, presses
from mission.scenario.motion_log import MotionLog
from mission.scenario.scenario_file import EStopExpect, Expect


def events(*items):
    return parse_events(list(items), "e", LupinConfig())


def log_of(rows) -> MotionLog:
    """(t, duty on all four wheels, true x) per control tick."""
    log = MotionLog(sim=None)
    for t, duty, x in rows:
        log.add(t, [duty] * 4, (x, 0.0, 0.0))
    return log


PRESS = ({"at": 1.0, "do": "estop", "engaged": True}, {"at": 2.0, "do": "estop", "engaged": False},
         {"at": 3.0, "do": "resume"})
DRIVING = [(0.9, 0.5, 0.27), (1.0, 0.5, 0.30), (1.1, 0.0, 0.315), (1.2, 0.0, 0.32), (1.3, 0.0, 0.32),
           (2.0, 0.0, 0.32), (2.5, 0.0, 0.321), (3.0, 0.0, 0.321), (3.1, 0.4, 0.33)]
"""Driving at 0.3 m/s; pressed at 1.0 after that instant's tick; coasts 2 cm; released at 2.0,
resumed at 3.0."""
AT_REST = [(t, 0.0, 0.5) for t in (0.9, 1.0, 1.1, 1.2, 2.0, 2.5, 3.0, 3.1)]
"""The base standing still (the arm busy at a pot, say) through the same press."""


def test_presses_pair_each_engagement_with_its_release_and_the_resume_after_it():
    e = events({"at": 10.0, "do": "estop", "engaged": True},
               {"at": 10.0, "do": "soft_estop", "engaged": True},
               {"at": 12.0, "do": "estop", "engaged": False},
               {"at": 13.0, "do": "resume"},  # refused: the soft stop still holds
               {"at": 14.0, "do": "soft_estop", "engaged": False},
               {"at": 16.0, "do": "resume"},
               {"at": 20.0, "do": "soft_estop", "engaged": True})
    found = presses(e, {i: 100.0 + ev.at for i, ev in enumerate(e)})
    assert [(p.at, p.released, p.resumed) for p in found] == [(110.0, 114.0, 116.0), (120.0, None, None)]


def test_presses_follow_the_instants_events_fired_not_the_script():
    # scripted at 10 with when_moving: it fired at 11.3; the release at 15 is paired with it
    e = events({"at": 10.0, "do": "estop", "engaged": True, "when_moving": 0.2},
               {"at": 15.0, "do": "estop", "engaged": False}, {"at": 16.0, "do": "resume"})
    [p] = presses(e, {0: 11.3, 1: 15.0, 2: 16.0})
    assert (p.at, p.released, p.resumed) == (11.3, 15.0, 16.0)
    assert presses(e, {1: 15.0, 2: 16.0}) == []  # the press never fired: no press, whatever the script says


def test_ticks_distance_speed_and_stillness():
    [p] = estop_figures(log_of(DRIVING), events(*PRESS), {0: 1.0, 1: 2.0, 2: 3.0}, 4.0)
    assert p.ticks_to_zero == 1 and p.distance_after == pytest.approx(0.02)
    assert p.speed == pytest.approx(0.3) and p.still_after_release and p.moved_after_release < 0.002


def test_late_zero_and_motion_before_resume_are_caught():
    rows = [(1.0, 0.5, 0.0), (1.1, 0.5, 0.03), (1.2, 0.0, 0.05), (2.0, 0.0, 0.05), (2.2, 0.3, 0.06), (2.4, 0.0, 0.08)]
    e = events(*PRESS[:2])
    [p] = estop_figures(log_of(rows), e, {0: 1.0, 1: 2.0}, 3.0)
    assert p.ticks_to_zero == 2
    assert not p.still_after_release and p.moved_after_release == pytest.approx(0.03)


def test_a_press_at_rest_fails_a_scenario_that_asks_for_speed():
    """The held-out case of issue 18: the press found the robot standing still; every duty was
    already zero, so 'ticks to zero' passed. Asking for speed at the press fails it, and says so."""
    x = EStopExpect(zero_duty_within_ticks=1, still_until_resume=True, min_speed_at_press=0.2)
    at_rest = estop(x, estop_figures(log_of(AT_REST), events(*PRESS), {0: 1.0, 1: 2.0, 2: 3.0}, 4.0), 0.0)
    by_name = {c.name: c for c in at_rest}
    assert by_name["estop.zero_duty_within_ticks"].passed  # what let the held-out scenario through
    speed = by_name["estop.min_speed_at_press"]
    assert not speed.passed
    assert speed.line() == ("  FAIL  estop.min_speed_at_press: expected every press to find the base driving at "
                            ">= 0.2 m/s (true speed), got speed at press: 0.00 m/s at 1.0 s (a press at rest tests nothing)")
    driving = estop(x, estop_figures(log_of(DRIVING), events(*PRESS), {0: 1.0, 1: 2.0, 2: 3.0}, 4.0), 0.0)
    assert all(c.passed for c in driving)


def test_a_press_that_never_fired_fails_and_is_named(tmp_path):
    """``when_moving`` that never came true: no press, and the judge says which event did not fire."""
    e = events({"at": 1.0, "do": "estop", "engaged": True, "when_moving": 5.0}, {"at": 2.0, "do": "estop", "engaged": False})
    log, fired = log_of(DRIVING), {1: 2.0}
    found = estop_figures(log, e, fired, 4.0)
    doc = {"outcome": "completed", "sim_time_s": 4.0, "anomalies": [], "pots": []}
    ending = Ending(doc, False, 0.0, "home", found, event_effects(log, e, fired, 4.0, None), 0.0, tmp_path)
    checks = {c.name: c for c in expectations(Expect(estop=EStopExpect(min_speed_at_press=0.2)), ending)}
    assert not checks["estop"].passed and checks["estop"].actual == "no press fired"
    assert not checks["events fired"].passed
    assert checks["events fired"].actual == "not fired: events[0] (do estop, at 1 s, when_moving 5 m/s)"


def _people_log(clearance, contacts, met):
    """A people log as the judge reads it: per walker the least clearance while moving, contacts
    begun while moving, and each time a walker came within 1.0 m."""
    from types import SimpleNamespace
    mins = {"W1": clearance, "W2": 2.0}
    return SimpleNamespace(min_clearance=mins, close_at={"W1": (12.0, 3.0, 0.5), "W2": (20.0, 1.0, 0.5)},
                           clearance=min(mins.values()), moving_contacts=contacts,
                           encounters=[{"walker": "W1", "t": 10.0 + k, "nearest_m": 0.4} for k in range(met)])


def test_the_people_judge_asks_for_clearance_no_contact_and_real_encounters():
    from mission.scenario.checks import people
    from mission.scenario.scenario_file import PeopleExpect
    x = PeopleExpect(min_clearance=0.25, contacts=0, encounters=2)
    good = {c.name: c for c in people(x, _people_log(0.31, [], 3), t0=2.0)}
    assert all(c.passed for c in good.values()) and set(good) == {"people.min_clearance", "people.contacts", "people.encounters"}
    assert good["people.min_clearance"].actual == "0.310 m (walker W1, at 10.0 s, robot at (3.00, 0.50))"
    bad = {c.name: c for c in people(x, _people_log(0.12, [(15.0, "walker_W1_leg_l")], 1), t0=2.0)}
    assert not any(c.passed for c in bad.values())
    assert bad["people.contacts"].line() == ("  FAIL  people.contacts: expected <= 0 contact(s) while moving, "
                                             "got 1 (walker_W1_leg_l at 13.0 s)")
    assert bad["people.encounters"].line() == ("  FAIL  people.encounters: expected >= 2 time(s) a walker came within "
                                               "1.0 m, got 1 (W1 at 8.0 s (0.40 m))")
