"""The person tracker on synthetic scans: what is a person and what is not, ids, velocity."""
from __future__ import annotations

import math

import numpy as np
import pytest

from nav.occupancy import OCCUPIED, OccupancyMap
from perception.people import PeopleConfig, PersonTracker
from perception.people.bodies import group
from perception.people.explained import StaticScene, explained_mask
from perception.people.segments import split
from tests.perception.people.synthetic import POT_RADIUS, Scene, greenhouse, mapped

ROBOT = (1.0, 2.0, 0.0)


def rows() -> tuple[Scene, list[tuple[float, float]]]:
    """A walled greenhouse with two rows of five pots either side of an aisle at y = 2."""
    s = greenhouse()
    return s, s.pot_row(2.0, 1.5, 5) + s.pot_row(2.0, 2.5, 5)


WALLS = mapped(greenhouse())
"""The map at patrol start: the greenhouse's walls."""


def track(scene: Scene, pots, scans: int = 1, robot=ROBOT, grid=WALLS) -> tuple:
    """People after ``scans`` 10 Hz scans of a still scene."""
    tracker = PersonTracker(PeopleConfig())
    static = StaticScene(grid, np.array(pots), POT_RADIUS, PeopleConfig().margin)
    people = ()
    for k in range(scans):
        pts = scene.scan(robot, seed=k)
        people = tracker.update(k * 0.1, pts, robot, static.explained(pts))
    return people


def near(people, x, y, within=0.3):
    return [p for p in people if math.hypot(p.x - x, p.y - y) <= within]


def test_pots_in_rows_and_walls_are_not_people():
    s, pots = rows()
    assert track(s, pots, scans=5) == ()


def test_unknown_pots_would_be_people_so_the_mask_matters():
    """The same rows with no pot known: the pots are unexplained and reported (the rule), which
    is what the known-pot mask takes away in the test above."""
    s, _ = rows()
    assert len(track(s, [], scans=2)) >= 6


def test_a_mapped_box_is_not_a_person_an_unmapped_one_is():
    s, pots = rows()
    s.box(4.0, 3.6, 0.6, 0.4)
    assert track(s, pots, scans=3, robot=(2.5, 3.0, 0.0), grid=mapped(s)) == ()
    assert len(near(track(s, pots, scans=3, robot=(2.5, 3.0, 0.0)), 4.0, 3.6, 0.5)) == 1


def test_a_standing_pair_of_legs_is_a_person():
    s, pots = rows()
    s.legs(3.5, 2.0, heading=math.pi)
    people = track(s, pots, scans=5)
    assert len(people) == 1
    p = people[0]
    assert math.hypot(p.x - 3.5, p.y - 2.0) < 0.1
    assert (p.vx, p.vy) == (0.0, 0.0)
    assert p.confidence >= 0.85
    assert 0.15 < p.radius < 0.45


def test_a_walking_person_keeps_its_id_and_its_velocity_is_estimated():
    def walker(k):
        s, _ = rows()
        return s.legs(5.0 - 0.1 * k, 2.0, heading=math.pi)  # 1 m/s towards the robot

    s, pots = rows()
    tracker = PersonTracker(PeopleConfig())
    static = StaticScene(WALLS, np.array(pots), POT_RADIUS, PeopleConfig().margin)
    ids = set()
    for k in range(20):
        pts = walker(k).scan(ROBOT, seed=k)
        people = tracker.update(k * 0.1, pts, ROBOT, static.explained(pts))
        assert len(people) == 1
        ids.add(people[0].id)
    p = people[0]
    assert ids == {p.id}
    assert abs(p.vx + 1.0) < 0.15 and abs(p.vy) < 0.15
    assert math.hypot(p.x - 3.1, p.y - 2.0) < 0.15
    assert p.confidence == pytest.approx(1.0)


def test_a_cart_pusher_is_one_person():
    s, pots = rows()
    s.cart_pusher(4.5, 2.0, heading=math.pi, width=0.7)  # pushing the cart towards the robot
    people = track(s, pots, scans=3)
    assert len(people) == 1
    p = people[0]
    assert 3.6 < p.x < 4.7 and abs(p.y - 2.0) < 0.3
    assert p.radius >= 0.3


def test_a_crouching_worker_is_a_person():
    s, pots = rows()
    s.crouching(3.5, 2.0, heading=math.pi / 2)
    people = track(s, pots, scans=3)
    assert len(people) == 1
    p = people[0]
    assert math.hypot(p.x - 3.5, p.y - 2.0) < p.radius  # its disc holds the body's centre
    assert people[0].confidence >= 0.5


def test_a_long_wall_with_no_map_is_not_a_person():
    s = greenhouse()
    assert track(s, [], scans=2, robot=(1.0, 1.0, 0.3), grid=None) == ()


def test_a_track_lives_through_a_short_occlusion_and_dies_after():
    s, pots = rows()
    s.legs(3.5, 2.0)
    empty, _ = rows()
    tracker = PersonTracker(PeopleConfig())
    static = StaticScene(WALLS, np.array(pots), POT_RADIUS, 0.1)
    seen = []
    for k, scene in enumerate([s, s, empty, empty, s] + [empty] * 12):
        pts = scene.scan(ROBOT, seed=k)
        seen.append(tracker.update(k * 0.1, pts, ROBOT, static.explained(pts)))
    assert seen[0][0].id == seen[3][0].id == seen[4][0].id  # coasted two scans, found again
    assert seen[3][0].confidence < seen[1][0].confidence
    assert seen[-1] == () and len(tracker.ids) == 0


def test_explained_mask_uses_the_map_cells_and_the_pots():
    grid = np.zeros((40, 40), np.int8)
    grid[10, 10] = OCCUPIED
    m = OccupancyMap(grid, 0.05, 0.0, 0.0)
    pts = np.array([[0.525, 0.525], [0.62, 0.525], [0.8, 0.525], [1.5, 1.5], [1.5, 1.72], [3.0, 3.0], [3.0, 3.12]])
    got = explained_mask(pts, m, np.array([[1.5, 1.5], [3.0, 3.0]]), 0.1, 0.1)
    # the cell, 0.1 m beside it, 0.3 m off; a pot's centre, its rim + 0.02; beyond the grid:
    # a pot there still explains
    assert got.tolist() == [True, True, False, True, False, True, True]


def reference_bodies(points: np.ndarray, robot: np.ndarray, c: PeopleConfig) -> list[tuple[float, float]]:
    """The bodies' centres by the rule, spelled out: segments of ``min_segment_points`` linked
    when both leg-wide with centres within ``pair_distance`` or their boxes within ``join_gap``,
    the components found by search, in the order of their first segment, each kept when it has
    ``min_body_points`` and is no wider than ``max_extent``; its centre the box's middle pushed
    ``depth`` away from the robot."""
    segs = split(points, np.hypot(*(points - robot).T), c.jump, c.jump_per_metre)
    kept = [k for k in range(len(segs.count)) if segs.count[k] >= c.min_segment_points]
    leg = {k: math.dist(segs.lo[k], segs.hi[k]) <= c.leg_width for k in kept}  # the box's diagonal

    def linked(a: int, b: int) -> bool:
        gap = np.maximum(np.maximum(segs.lo[b] - segs.hi[a], segs.lo[a] - segs.hi[b]), 0.0)
        return (leg[a] and leg[b] and math.dist(segs.centre[a], segs.centre[b]) <= c.pair_distance) \
            or math.hypot(*gap) <= c.join_gap

    out, done = [], set()
    for a in kept:
        if a in done:
            continue
        body, todo = {a}, [a]
        while todo:
            b = todo.pop()
            for n in kept:
                if n not in body and linked(b, n):
                    body.add(n)
                    todo.append(n)
        done |= body
        lo = np.min([segs.lo[k] for k in body], axis=0)
        hi = np.max([segs.hi[k] for k in body], axis=0)
        if sum(segs.count[k] for k in body) >= c.min_body_points and math.dist(lo, hi) <= c.max_extent:
            mid = (lo + hi) / 2
            out.append(tuple(mid + c.depth * (mid - robot) / np.linalg.norm(mid - robot)))
    return out


def test_bodies_are_the_connected_components_of_the_links_in_order():
    c, rng = PeopleConfig(), np.random.default_rng(5)
    for _ in range(60):
        blobs = [rng.uniform(-3, 3, 2) + rng.normal(0, rng.uniform(0.01, 0.3), (int(rng.integers(1, 20)), 2))
                 for _ in range(int(rng.integers(1, 12)))]
        points, robot = np.concatenate(blobs), rng.uniform(-0.5, 0.5, 2) + 5.0
        segs = split(points, np.hypot(*(points - robot).T), c.jump, c.jump_per_metre)
        got = group(points, segs, robot, c).centre
        assert np.allclose(got, np.array(reference_bodies(points, robot, c)).reshape(-1, 2), atol=1e-9)