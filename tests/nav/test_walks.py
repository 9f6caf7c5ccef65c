"""A person's last walk, remembered by id (nav.walks): where a walker who pauses walks again."""
from __future__ import annotations

import math

from hw.odometry import Pose2D
from hw.people import Person
from nav.config import NavConfig
from nav.people_nearby import PeopleNearby
from nav.walks import KEPT, PAUSE, SWEEP, TURN_KEPT, Walks


def test_a_persons_walk_outlives_their_track_and_a_paused_walker_keeps_it():
    """A cart pusher walked south, was lost a moment at the end of their walk and came back
    under their id, paused (the tracker gives a track born where a person was lost their id):
    their walk is still theirs (safety.people seed 1, 2,555 s: with no walk, no lane, and the
    robot stepped into it)."""
    now: list[Person] = [Person(7, 2.0, 3.0, 0.0, -1.0, 0.25, 0.9)]
    walks = Walks(lambda: now)
    walks()
    now[:] = [Person(7, 2.0, 2.6, 0.0, -1.0, 0.25, 0.9)]  # 0.4 m on: a walk
    walks()
    now[:] = []  # lost for a few scans
    walks()
    now[:] = [Person(7, 2.0, 2.0, 0.03, 0.0, 0.25, 0.9)]  # back, standing at the end of their walk
    (p,) = walks()
    assert walks.last(p) == (0.0, -1.0) and walks.paused(p) == (0.0, -1.0)
    walking = Person(7, 2.0, 2.0, 0.0, 0.9, 0.25, 0.9)  # walking back north: their own velocity
    assert walks.last(walking) == (0.0, 0.9) and walks.paused(walking) is None
    assert walks.paused(Person(8, 0.0, 0.0, 0.0, 0.0, 0.25, 0.9)) is None  # never walked


def test_only_the_latest_walks_are_kept():
    now = [Person(7, 2.0, 3.0, 0.0, -1.0, 0.25, 0.9)]
    walks = Walks(lambda: now)
    walks()
    now[:] = [Person(7, 2.0, 2.5, 0.0, -1.0, 0.25, 0.9)]
    walks()
    paused = Person(7, 2.0, 2.0, 0.0, 0.0, 0.25, 0.9)
    assert walks.paused(paused) == (0.0, -1.0)
    for x in (0.0, 0.5):
        now[:] = [Person(k, x, 0.0, 1.0, 0.0, 0.25, 0.9) for k in range(100, 100 + 2 * KEPT)]
        walks()
    assert walks.paused(paused) is None and walks.paused(Person(100 + 2 * KEPT - 1, 0, 0, 0, 0, 0.25, 0.9)) == (1.0, 0.0)


def test_the_refuge_keeps_out_of_a_paused_walkers_walk():
    """``PeopleNearby.walks`` gives the refuge a paused person's remembered walk as theirs."""
    now = [Person(7, 2.0, 3.0, 0.0, -1.0, 0.25, 0.9)]
    nearby = PeopleNearby(NavConfig(), lambda: now, Pose2D)
    nearby.counted()
    now[:] = [Person(7, 2.0, 2.5, 0.0, -1.0, 0.25, 0.9)]
    nearby.counted()
    now[:] = [Person(7, 2.0, 2.0, 0.0, 0.0, 0.25, 0.9)]
    ((x, y, vx, vy, r),) = nearby.walks(nearby.counted())
    assert (x, y, vx, vy) == (2.0, 2.0, 0.0, -1.0)


def test_a_pause_longer_than_a_turn_is_someone_standing():
    """A worker who walked to a bench and works there is standing, not about to walk back
    (walker-aisle-worker: kept out of their walk both ways for good, the robot never worked
    their aisle again)."""
    t = [0.0]
    now = [Person(7, 2.0, 3.0, 0.0, 0.8, 0.25, 0.9)]
    walks = Walks(lambda: now, lambda: t[0])
    walks()
    t[0] = 0.4
    now[:] = [Person(7, 2.0, 3.32, 0.0, 0.8, 0.25, 0.9)]
    walks()
    now[:] = [Person(7, 2.0, 3.4, 0.0, 0.0, 0.25, 0.9)]
    t[0] = PAUSE - 0.5
    (p,) = walks()
    assert walks.paused(p) == (0.0, 0.8)
    t[0] = PAUSE + 0.5
    assert walks.paused(p) is None and walks.last(p) == (0.0, 0.8)  # standing; the refuge still knows their line


def test_a_striders_heading_is_where_they_walked_not_their_velocity_now():
    """A cart pushed north at 0.7 m/s, the tracker's velocity swinging 20 deg either way scan
    to scan (safety.people seed 2, 1,403 s): the lane goes where they walked, at their speed."""
    clock = [0.0]
    now: list[Person] = []
    walks = Walks(lambda: now, lambda: clock[0])
    for k in range(12):  # 10 Hz, 1.1 s
        clock[0] = 0.1 * k
        swing = 0.25 if k % 2 else -0.25
        now[:] = [Person(3, 6.0, 2.0 + 0.07 * k, swing, 0.66, 0.4, 0.9)]
        (p,) = walks()
    vx, vy = walks.last(p)
    assert abs(vx) < 0.02 and abs(math.hypot(vx, vy) - math.hypot(0.25, 0.66)) < 1e-9
    assert vy > 0.6
    stopped = Person(3, 6.0, 2.8, 0.05, 0.0, 0.4, 0.9)  # they pause: their walk is remembered, heading and all
    now[:] = [stopped]
    clock[0] = 1.2
    walks()
    assert abs(walks.paused(stopped)[0]) < 0.02


def test_where_a_walker_turned_round_is_remembered_for_a_while():
    """A cart pusher walks north to the end of their cross aisle, pauses and turns (the tracked
    circle holds pusher and cart): the turn is remembered with the reach of a turning cart,
    seen again it is the same turn, and it is forgotten ``TURN_KEPT`` after it was last seen."""
    t = [0.0]
    now = [Person(4, 1.0, 5.5, 0.0, 0.9, 0.45, 0.9)]
    walks = Walks(lambda: now, lambda: t[0])
    walks()
    t[0] = 0.5
    now[:] = [Person(4, 1.0, 5.95, 0.0, 0.9, 0.45, 0.9)]
    walks()
    assert walks.turns() == []  # walking: no turn
    t[0] = 1.0
    now[:] = [Person(4, 1.0, 6.5, 0.05, 0.0, 0.45, 0.9)]  # paused at the end
    walks()
    assert walks.turns() == [(1.0, 6.5, SWEEP * 0.45)]
    t[0] = 2.0
    now[:] = [Person(4, 1.2, 6.6, 0.0, 0.05, 0.5, 0.9)]  # the cart swings: the same turn, wider
    walks()
    assert walks.turns() == [(1.2, 6.6, SWEEP * 0.5)]
    t[0] = 2.0 + TURN_KEPT + 0.1
    assert walks.turns() == []


def test_someone_standing_from_the_start_turns_nowhere():
    """Only a pause after a walk is a turn or keeps a walk: a worker who has not walked (their
    track's velocity jittering past a stride a moment: safety.people seed 105's crouching worker,
    whose blip laid a lane 4 m along the side aisle beside them), or stood longer than a pause,
    adds none."""
    t = [0.0]
    now = [Person(5, 3.0, 3.0, 0.0, 0.0, 0.3, 0.9)]
    walks = Walks(lambda: now, lambda: t[0])
    walks()
    for k, v in enumerate((0.5, 0.45, 0.0)):  # a blip of velocity, a centimetre moved
        t[0] = 0.1 * (k + 1)
        now[:] = [Person(5, 3.0 + 0.005 * k, 3.0, v, 0.0, 0.3, 0.9)]
        walks()
    assert walks.turns() == []
    crouching = now[0]  # nor is the blip a walk: no lane along it
    assert walks.paused(crouching) is None and walks.last(crouching) == (0.0, 0.0)
    now[:] = [Person(6, 0.0, 0.0, 0.9, 0.0, 0.25, 0.9)]
    walks()
    t[0] = PAUSE + 1.0
    now[:] = [Person(6, 0.5, 0.0, 0.0, 0.0, 0.25, 0.9)]
    walks()
    assert walks.turns() == []


def test_someone_who_stops_for_the_robot_has_not_turned():
    """A grower who yields stops 0.3 m short of the robot: not a turn (taken for one, it put the
    robot out of every refuge near them, safety.people seed 1, 119 s); the same pause 1 m off is."""
    t = [0.0]
    gap = [0.3]
    now = [Person(4, 11.0, 2.5, 0.9, 0.0, 0.43, 0.9)]
    walks = Walks(lambda: now, lambda: t[0], lambda p: gap[0])
    walks()
    t[0] = 0.5
    now[:] = [Person(4, 11.4, 2.5, 0.9, 0.0, 0.43, 0.9)]
    walks()
    t[0] = 1.0
    now[:] = [Person(4, 11.4, 2.5, 0.0, 0.0, 0.43, 0.9)]
    walks()
    assert walks.turns() == []
    gap[0] = 1.0
    walks()
    assert walks.turns() == [(11.4, 2.5, SWEEP * 0.43)]


def test_a_paused_pacers_way_back_is_their_whole_last_walk():
    """A cart pusher who walked 4.5 m up their aisle and stands at its end walks all of it back
    (safety.people seed 104, 650 s: the planner took the aisle 4 m from them for the way home,
    and they came back down it into the robot): the way back reaches where that walk began,
    over a moment's slowing in it, but not past the turn before it."""
    t = [0.0]
    now = [Person(7, 1.0, 0.0, 0.0, -1.0, 0.4, 0.9)]  # walking south first
    walks = Walks(lambda: now, lambda: t[0])
    walks()
    for k in range(1, 20):  # turned at y = -0.5 and walked north 4.5 m, slowing once
        t[0] = 0.5 * k
        y = -0.5 + 0.25 * (k - 1)
        now[:] = [Person(7, 1.0, y, 0.0, 0.3 if k == 8 else 0.5, 0.4, 0.9)]
        walks()
    t[0] += 1.0
    now[:] = [Person(7, 1.0, 4.0, 0.0, 0.0, 0.4, 0.9)]
    (p,) = walks()
    back = walks.way_back(p)
    assert back is not None and math.hypot(back[0], back[1] + 4.5) < 0.3, back
    assert walks.way_back(Person(7, 1.0, 4.0, 0.0, 0.5, 0.4, 0.9)) is None  # walking: not paused
