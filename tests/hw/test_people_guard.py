"""The people guard (hw/people_guard.py): at most 0.15 m/s within 1.0 m of a person body to
body, no motion towards a person nearer than 0.5 m (sideways and away pass), unsure tracks and
nobody change nothing, the robot's heading and odom pose are honoured, and on the base it sits
below the e-stop and above the collision monitor, for every mux source."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hw.config import HwConfig, PeopleGuardConfig
from hw.interfaces import Twist
from hw.odometry import Pose2D
from hw.people import Person
from hw.people_guard import AWAY, NONE, SLOW, STILL, PeopleGuard
from tests.fixtures import make_base_rig

R = 0.22


def guard(*people: Person, pose: Pose2D = Pose2D()) -> PeopleGuard:
    return PeopleGuard(PeopleGuardConfig(), lambda: pose, R, lambda: people)


def at(x: float, y: float, radius: float = 0.2, confidence: float = 0.9) -> Person:
    return Person(1, x, y, 0.0, 0.0, radius, confidence)


def speed(t: Twist) -> float:
    return math.hypot(t.vx, t.vy)


def test_nobody_or_far_away_changes_nothing():
    t = Twist(0.4, 0.1, 0.3)
    assert guard().judge(t) == t
    g = guard(at(0.0, 1.5))  # 1.08 m body to body
    assert g.judge(t) == t and g.verdict.action == NONE


def test_within_a_metre_the_speed_is_capped_at_0_15_keeping_the_curvature():
    g = guard(at(0.0, 1.3))  # 0.88 m beside the path
    out = g.judge(Twist(0.4, 0.0, 0.2))
    assert speed(out) == pytest.approx(0.15)
    assert out.wz / out.vx == pytest.approx(0.2 / 0.4)
    assert g.verdict.action == SLOW and g.verdict.nearest == pytest.approx(0.88)
    assert g.judge(Twist(0.1, 0.0, 0.0)) == Twist(0.1, 0.0, 0.0)  # already slow enough


def test_nearer_than_half_a_metre_motion_towards_is_removed_sideways_and_away_pass():
    g = guard(at(0.8, 0.0))  # 0.38 m ahead
    assert speed(g.judge(Twist(0.3, 0.0, 0.0))) == pytest.approx(0.0)
    assert g.verdict.action == AWAY and g.verdict.holding
    side = g.judge(Twist(0.1, 0.1, 0.0))
    assert side.vx == pytest.approx(0.0) and side.vy == pytest.approx(0.1)  # the strafe past them stays
    assert not g.verdict.holding
    back = g.judge(Twist(-0.1, 0.0, 0.0))
    assert back == Twist(-0.1, 0.0, 0.0)  # away from them, at most 0.15 m/s: untouched


def test_someone_at_arms_length_stops_every_motion_turning_and_away_included():
    g = guard(at(0.0, 0.62))  # 0.20 m beside the robot: they walked up to it
    wait = PeopleGuardConfig().still_wait
    for now in (10.0, 10.0 + wait / 2, 10.0 + wait - 0.01):
        for t in (Twist(-0.1, 0.0, 0.0), Twist(0.0, -0.1, 0.0), Twist(0.0, 0.0, 0.3)):
            assert g.judge(t, now) == Twist(0.0, 0.0, 0.0)
            assert g.verdict.action == STILL and g.verdict.holding
    # they stay: after ``still_wait`` the robot may step away from them, never towards
    assert g.judge(Twist(0.0, -0.1, 0.0), 10.0 + wait) == Twist(0.0, -0.1, 0.0)
    assert speed(g.judge(Twist(0.0, 0.1, 0.0), 10.0 + wait)) == pytest.approx(0.0)
    g = guard(at(0.0, 0.72))  # 0.30 m: away and sideways pass at once
    assert g.judge(Twist(0.0, -0.1, 0.0), 10.0) == Twist(0.0, -0.1, 0.0)


def test_someone_passing_close_by_or_walking_into_the_robot_counts_as_there_already():
    passing = Person(1, 0.15, 0.66, -0.8, 0.0, 0.2, 0.9)  # 0.26 m off, crossing to 0.24 m beside it at 0.8 m/s
    g = guard(passing)
    assert g.verdict.action == NONE
    assert g.judge(Twist(-0.1, 0.0, 0.0), 5.0) == Twist(0.0, 0.0, 0.0) and g.verdict.action == STILL
    going = Person(1, 0.0, 1.02, 0.0, 0.8, 0.2, 0.9)  # walking off
    assert guard(going).judge(Twist(-0.1, 0.0, 0.0), 5.0) == Twist(-0.1, 0.0, 0.0)
    coming = Person(1, 0.0, 0.82, 0.0, -0.8, 0.2, 0.9)  # 0.40 m beside, walking straight at it
    g = guard(coming)
    assert g.judge(Twist(0.0, -0.1, 0.0), 5.0) == Twist(0.0, 0.0, 0.0)  # too late to step aside: stand
    assert g.verdict.action == STILL
    g = guard(Person(1, 0.0, 1.62, 0.0, -0.8, 0.2, 0.9))  # 1.2 m off: out of their way, yes
    assert g.judge(Twist(0.0, -0.1, 0.0), 5.0) == Twist(0.0, -0.1, 0.0)
    past = Person(1, 0.53, 0.6, 0.0, -0.8, 0.2, 0.9)  # closing fast, but their walk passes 0.11 m beside it
    g = guard(past)
    assert g.judge(Twist(0.0, -0.1, 0.0), 5.0) == Twist(0.0, 0.0, 0.0) and g.verdict.action == STILL


def test_two_people_either_side_ahead_stop_the_robot_between_them():
    g = guard(at(0.5, 0.5), at(0.5, -0.5))
    out = g.judge(Twist(0.15, 0.0, 0.0))
    assert speed(out) == pytest.approx(0.0)
    assert g.judge(Twist(-0.15, 0.0, 0.0)) == Twist(-0.15, 0.0, 0.0)


def test_between_two_people_nearly_opposite_the_way_square_to_both_stays_open():
    """A standing worker 0.45 m to one side, a cart 0.2 m to the other: a step that closes on the
    worker loses just that part (the least taken out) and slides out between them."""
    worker, cart = at(0.77, 0.5, 0.27), at(-0.56, -0.61, 0.47)
    g = guard(worker, cart)
    step = Twist(-0.025, 0.147, 0.0)  # to a refuge past the worker's shoulder
    wait = PeopleGuardConfig().still_wait
    g.judge(step, 0.0)  # the cart at arm's length: waited out first
    out = g.judge(step, wait)
    v, s = np.array([out.vx, out.vy]), np.array([step.vx, step.vy])
    u = np.array([worker.x, worker.y]) / math.hypot(worker.x, worker.y)
    assert g.verdict.action == AWAY and not g.verdict.holding
    assert v == pytest.approx(s - (s @ u) * u)  # the least taken out: the part towards the worker
    assert v @ u == pytest.approx(0.0, abs=1e-9) and v @ np.array([cart.x, cart.y]) <= 1e-9
    assert speed(g.judge(Twist(0.1, 0.06, 0.0), wait)) == pytest.approx(0.0)  # straight at the worker: nothing


def polar(r: float, degrees: float) -> tuple[float, float]:
    return r * math.cos(math.radians(degrees)), r * math.sin(math.radians(degrees))


def test_a_person_the_scan_shows_beyond_half_a_metre_does_not_close_the_way_out():
    """safety.people seed 113 at 681 s, as the guard saw it (base frame): a worker behind, their
    circle 0.47 m off but their legs' returns 0.58 m; a cart ahead, its circle 0.13 m off, its
    nearest return 0.29 m. Judged on the circle the worker made a ring with the cart and the
    robot's step to its refuge was held for 2,400 s; on the body the scan shows it passes."""
    worker, cart = at(*polar(0.96, 165.0), 0.27), at(*polar(0.82, -7.7), 0.47)
    returns = np.array([polar(0.80, 157.8), polar(0.51, -29.6)])
    g = PeopleGuard(PeopleGuardConfig(), Pose2D, R, lambda: (worker, cart), returns=lambda: returns)
    step = Twist(-0.091, -0.119, 0.0)
    assert g.judge(step, 0.0) == Twist(0.0, 0.0, 0.0)  # the cart at arm's length: waited out first
    assert g.judge(step, PeopleGuardConfig().still_wait) == step
    assert g.verdict.nearest == pytest.approx(0.29)
    g = PeopleGuard(PeopleGuardConfig(), Pose2D, R, lambda: (worker, cart), returns=lambda: returns[1:])
    g.judge(step, 0.0)
    assert g.judge(step, PeopleGuardConfig().still_wait) == Twist(0.0, 0.0, 0.0)  # the worker unseen: their circle counts


def test_the_step_away_from_everyone_near_closes_on_none_of_them_and_there_may_be_none():
    """``escape``, taken by the navigator when its own step has been held: between a worker and
    a cart whose corner the returns show, straight away from both (safety.people seed 113)."""
    worker, cart = at(0.77, 0.5, 0.27), at(-0.56, -0.61, 0.47)
    corner = np.array([[-0.35, -0.45]])
    g = PeopleGuard(PeopleGuardConfig(), Pose2D, R, lambda: (worker, cart), returns=lambda: corner)
    out = g.escape(0.15)
    v = np.array([out.vx, out.vy])
    assert speed(out) == pytest.approx(0.15) and out.wz == 0.0
    for p in (np.array([worker.x, worker.y]), np.array([cart.x, cart.y]), corner[0]):
        assert v @ p < 0.0
    g.judge(out, 0.0)  # the cart at arm's length: waited out first
    assert g.judge(out, PeopleGuardConfig().still_wait) == out  # then the guard lets it through whole


def test_ringed_round_the_base_creeps_along_the_way_that_closes_least_and_no_faster():
    """safety.people seed 113 at 1,212 s (base frame): a worker 0.48 m off, a cart 0.28 m off
    on the other side, 168 deg apart; every way closes on one of them, and standing the robot
    waited for good while the cart waited for it. The escape creeps down the middle of the way
    between them, closing on either at most ``ring_closing``; the guard lets that, and only
    that, through."""
    worker, cart = at(*polar(0.97, -107.7), 0.27), at(*polar(0.97, 75.8), 0.47)
    returns = np.array([polar(0.70, -115.0), polar(0.50, 59.3)])
    cfg = PeopleGuardConfig()
    g = PeopleGuard(cfg, Pose2D, R, lambda: (worker, cart), returns=lambda: returns)
    out = g.escape(0.15)
    v = np.array([out.vx, out.vy])
    toward = np.vstack([[worker.x, worker.y], [cart.x, cart.y], returns])
    toward /= np.hypot(toward[:, 0], toward[:, 1])[:, None]
    assert 0.05 < speed(out) <= 0.15 and out.wz == 0.0
    assert 0.0 < (toward @ v).max() <= cfg.ring_closing + 1e-9
    assert g.judge(out, 0.0) == out and g.verdict.action == NONE  # nobody at arm's length: no wait
    for turn in (-15.0, 15.0):  # 15 deg off that way closes 0.05 m/s on someone: none of it
        c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
        assert speed(g.judge(Twist(c * out.vx - s * out.vy, s * out.vx + c * out.vy, 0.0), 0.0)) == pytest.approx(0.0)
    assert speed(g.judge(Twist(0.1, -0.1, 0.0), 0.0)) == pytest.approx(0.0)  # nor towards the worker
    three = guard(at(1.2, 0.0, 0.5), at(-0.6, 1.04, 0.5), at(-0.6, -1.04, 0.5))  # 0.48 m off all round
    step = three.escape(0.15)
    assert speed(step) == pytest.approx(cfg.ring_closing / 0.5, rel=1e-2)  # 60 deg off either side of its way
    never = PeopleGuard(PeopleGuardConfig(ring_closing=0.0), Pose2D, R, lambda: (worker, cart), returns=lambda: returns)
    assert speed(never.escape(0.15)) == pytest.approx(0.0)
    assert guard(at(0.0, 1.5)).escape(0.15) == Twist(0.0, 0.0, 0.0)  # nobody near
    assert guard().escape(0.15) == Twist(0.0, 0.0, 0.0)


def test_people_are_in_odom_and_towards_is_judged_in_the_base_frame():
    # the robot at (2, 1) facing +y: a person at odom (2, 1.8) is straight ahead of it
    g = guard(at(2.0, 1.8), pose=Pose2D(2.0, 1.0, math.pi / 2))
    assert speed(g.judge(Twist(0.1, 0.0, 0.0))) == pytest.approx(0.0)
    assert g.judge(Twist(0.0, 0.1, 0.0)) == Twist(0.0, 0.1, 0.0)  # body +y is odom -x: across


def test_a_step_away_from_a_carts_middle_is_not_let_towards_its_corner():
    """A cart's track is one circle round pusher and cart; its scan returns say where the body
    ends. A strafe away from the circle's centre that closes on the cart's nearest corner is
    stopped by the returns, not by the circle (safety.people, seed 111 at 2,019 s)."""
    cart = Person(1, 0.5, 0.55, 0.0, 0.0, 0.45, 0.9)  # 0.07 m off by its circle
    corner = np.array([[0.35, 0.12], [0.55, 0.12], [0.35, 0.3]])  # its near face, 0.15 m off
    pot = np.array([[0.3, -0.2]])  # close by, but not on the cart's body
    step = Twist(0.07, -0.08, 0.0)  # away from the circle's centre, towards the corner
    wait = PeopleGuardConfig().still_wait
    by_circle = PeopleGuard(PeopleGuardConfig(), Pose2D, R, lambda: (cart,), returns=lambda: pot)
    by_circle.judge(step, 0.0)  # standing: at arm's length by the circle, waited out first
    assert by_circle.judge(step, wait) == step
    g = PeopleGuard(PeopleGuardConfig(), Pose2D, R, lambda: (cart,), returns=lambda: np.vstack([corner, pot]))
    assert g.judge(step, 0.0) == Twist(0.0, 0.0, 0.0) and g.verdict.action == STILL
    out = g.judge(step, wait)
    v = np.array([out.vx, out.vy])
    assert g.verdict.action == AWAY and 0.0 < speed(out) < speed(step)
    assert v @ corner[0] <= 1e-9 and v @ np.array([cart.x, cart.y]) <= 1e-9  # from the corner and the middle
    assert g.verdict.nearest == pytest.approx(math.hypot(0.35, 0.12) - R)  # the body as the scan shows it


def test_unsure_tracks_do_not_count():
    g = guard(at(0.8, 0.0, confidence=0.3))
    assert g.judge(Twist(0.3, 0.0, 0.0)) == Twist(0.3, 0.0, 0.0)


class Recorder:
    """The collision monitor's place: records what it was handed and stops everything."""

    def __init__(self):
        self.seen: list[Twist] = []

    def filter(self, twist: Twist, now: float) -> Twist:
        self.seen.append(twist)
        return Twist(0.0, 0.0, twist.wz)


@pytest.mark.parametrize("source", ["auto", "manual", "joy"])
def test_on_the_base_every_source_is_guarded_below_the_estop_and_above_the_monitor(source):
    rig = make_base_rig(HwConfig())
    person = [at(1.0, 0.0)]  # 0.58 m ahead: slow
    below = Recorder()
    rig.base.guard = PeopleGuard(PeopleGuardConfig(), lambda: rig.base.odometry.pose, R, lambda: person, below)
    rig.mux.publish(source, Twist(0.3, 0.0, 0.0), 0.0)
    rig.base.tick(0.0)
    assert speed(below.seen[-1]) == pytest.approx(0.15)  # the monitor is handed the guarded twist
    assert rig.base.command == Twist(0.0, 0.0, 0.0)  # and has the last word
    person.clear()
    rig.button.level = rig.config.estop.engaged_level
    rig.base.tick(0.1)
    assert rig.base.source == "estop" and len(below.seen) == 1  # the e-stop is above every guard


def test_the_cap_holds_over_a_whole_approach_on_the_simulated_wheels():
    """Driving at 0.4 m/s towards someone 2 m ahead, the wheels never carry the robot faster than
    0.15 m/s once inside 1 m, and it never closes inside 0.5 m (its own odometry judges)."""
    rig = make_base_rig(HwConfig())
    person = at(2.0 + R + 0.2, 0.0)
    rig.base.guard = PeopleGuard(PeopleGuardConfig(), lambda: rig.base.odometry.pose, R, lambda: [person])
    speeds, gaps = [], []
    for k in range(120):
        now = 0.1 * k
        rig.mux.publish("auto", Twist(0.4, 0.0, 0.0), now)
        rig.scheduler.run_until(now)
        p = rig.base.odometry.pose
        gaps.append(2.0 + R + 0.2 - p.x - 0.2 - R)
        speeds.append(rig.base.command.vx)
    gaps, speeds = np.array(gaps), np.array(speeds)
    assert speeds[gaps > 1.05].max() == pytest.approx(0.4)
    assert speeds[gaps < 0.95].max() <= 0.15 + 1e-9
    assert gaps.min() >= 0.45  # the twist towards them is zero from 0.5 m; a beat's coasting at most
