"""The runtime's people (mission/runtime/people.py) on synthetic scans: nothing is tracked until
the patrol names its pots; then pots and mapped walls are not people and a worker's legs are, in
odom; a wall the first map lacked is taken in once SLAM's map has it (long: structure), while the
worker, written into the live map as they stand, stays a person (small: never taken in); the
rules act on tracks that have walked, from then on, standing or not."""
from __future__ import annotations

import math

import numpy as np

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.robot_outline import Capsules, Outline
from mission.runtime.greenhouse import floor_seen, kept, without
from mission.runtime.people import LEG_SCANS, LEGS_SEEN, LOST_KEEP, People
from mission.runtime.stood_at_start import FORGET, REACH, SEEN, StoodAtStart, clear_round
from nav.grid_geometry import GridGeometry
from nav.frames import compose
from nav.occupancy import OccupancyMap
from nav.structure import long_components
from perception.people.config import PeopleConfig
from tests.perception.people.synthetic import POT_RADIUS, greenhouse, mapped

ODOM = Pose2D(1.0, 2.5, 0.0)
MOUNT = Pose2D(0.115, 0.0, 0.0)
CHASSIS = Outline(0.165, 0.13)
WORKER = (3.0, 2.5)


def scene():
    """The greenhouse, two rows of pots and a column of them before the east wall, which they
    break into short arcs as the robot sees it."""
    s = greenhouse()
    pots = s.pot_row(2.0, 1.5, 4) + s.pot_row(2.0, 3.5, 4)
    for y in np.arange(0.4, 4.7, 0.4):
        pots += s.pot_row(7.6, float(y), 1)
    return s, pots


def lidar_scan(points: np.ndarray, stamp: float) -> LidarScan:
    """Scene-frame returns (scan order) as the lidar on the robot at ``ODOM`` measured them."""
    lx, ly = ODOM.x + MOUNT.x, ODOM.y + MOUNT.y
    d = points - [lx, ly]
    return LidarScan(stamp, np.arctan2(d[:, 1], d[:, 0]).astype(np.float32),
                     np.hypot(d[:, 0], d[:, 1]).astype(np.float32))


def with_cells(m: OccupancyMap, x: float, y: float, r: float, value: int = 100) -> OccupancyMap:
    """``m`` with the disc of radius ``r`` at (x, y) set to ``value`` (100 occupied, 0 free)."""
    occ = m.occupancy.copy()
    g = m.geometry
    gy, gx = np.mgrid[0:g.height, 0:g.width]
    cx, cy = g.centre_of(gx, gy)
    occ[np.hypot(cx - x, cy - y) <= r] = value
    return OccupancyMap(occ, m.resolution, m.origin_x, m.origin_y)


def first_and_structure(first: OccupancyMap, live: OccupancyMap, structure: OccupancyMap | None = None) -> np.ndarray:
    """What the scene takes for the greenhouse (``People._freeze``): the structure of
    ``structure`` (``live`` by default) and the first map's cells."""
    return long_components(structure or live, PeopleConfig().max_extent) | kept(first, live)


class Rig:
    def __init__(self, first: OccupancyMap, heading: float = math.pi / 2, thing=None, body: Outline = CHASSIS,
                 config: PeopleConfig = PeopleConfig()):
        s, self.pots = scene()
        if thing is None:
            s.legs(*WORKER, heading=heading)  # facing north: one leg behind the other, seen side-on
        else:
            thing(s)
        self.points = s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))
        self.map = first
        self.t = 0.0
        self.people = People(config, lambda: lidar_scan(self.points, self.t), lambda: ODOM, MOUNT,
                             Pose2D, lambda: self.map, lambda: body, 0.02)

    def ticks(self, n: int):
        for _ in range(n):
            self.t = round(self.t + 0.1, 6)
            self.people.tick(self.t)
        return self.people.current()


def test_no_one_is_tracked_until_the_patrol_names_its_pots_then_only_the_worker():
    walls, pots = scene()
    rig = Rig(mapped(walls))
    assert rig.ticks(5) == ()
    rig.people.watch(pots, 0.10)
    people = rig.ticks(5)
    assert len(people) == 1
    p = people[0]
    assert math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15 and p.confidence >= 0.5


def test_a_worker_pressed_to_the_chassis_front_is_a_person_and_the_arm_out_to_the_side_is_not():
    """The robot's own returns are dropped by its outline as it stands, not by a 0.25 m circle:
    that circle hid the legs of a worker who walked up to the robot's front (safety.people seed
    115, 516 s), here 0.19-0.25 m from its centre."""
    arm = Capsules(np.array([[[0.0, 0.1], [0.0, 0.4]]]), 0.03)  # reaching out to the left
    def against_the_robot(s):
        s.legs(ODOM.x + 0.27, ODOM.y)  # legs side by side, facing the robot's front
        s.box(ODOM.x, ODOM.y + 0.28, 0.04, 0.2)  # what the lidar sees of the arm

    walls, pots = scene()
    rig = Rig(mapped(walls), thing=against_the_robot, body=Outline(0.165, 0.13, arm))
    near = np.hypot(rig.points[:, 0] - ODOM.x, rig.points[:, 1] - ODOM.y)
    assert (near < 0.25).sum() >= 4  # the worker's front returns, inside the old circle
    rig.people.watch(pots, 0.10)
    rig.ticks(5)
    shown = rig.people.confident()
    assert len(shown) == 1 and math.hypot(shown[0].x - ODOM.x - 0.27, shown[0].y - ODOM.y) < 0.1
    assert not any(abs(p.x - ODOM.x) < 0.1 and p.y - ODOM.y > 0.15 for p in rig.people.tracks)  # no arm
    circle = Rig(mapped(walls), thing=against_the_robot, body=Outline(0.165, 0.13, arm),
                 config=PeopleConfig(min_range=0.25))
    circle.people.watch(pots, 0.10)
    circle.ticks(5)
    assert circle.people.confident() == ()


def test_a_wall_the_first_map_lacked_is_taken_in_from_slam_but_a_standing_worker_never_is():
    walls, pots = scene()
    east = walls.walls.pop(1)  # the first map never saw the east wall behind its pots
    first = mapped(walls)
    walls.walls.insert(1, east)
    rig = Rig(first)
    rig.people.watch(pots, 0.10)
    on_wall = rig.points[:, 0] > 7.9
    legs = np.hypot(rig.points[:, 0] - WORKER[0], rig.points[:, 1] - WORKER[1]) < 0.3
    assert on_wall.sum() > 10 and legs.sum() > 5
    rig.ticks(1)
    assert not rig.people.scene.explained(rig.points)[on_wall].any()
    rig.map = with_cells(mapped(walls), *WORKER, 0.2)  # SLAM's map now: the east wall, and the worker
    after = rig.ticks(5)
    explained = rig.people.scene.explained(rig.points)
    assert explained[on_wall].all() and not explained[legs].any()
    assert any(math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15 for p in after)


def test_structure_is_what_is_longer_than_a_person_plus_the_first_map():
    walls, _ = scene()
    first = OccupancyMap(np.zeros_like(mapped(walls).occupancy), 0.05, -0.1, -0.1)
    first = with_cells(first, 6.0, 1.0, 0.1)  # something small the first map held
    live = with_cells(mapped(walls), *WORKER, 0.2)
    taken = first_and_structure(first, live)
    g = live.geometry
    def at(x, y):
        ix, iy = g.cell_of(x, y)
        return bool(taken[iy, ix])
    assert at(4.0, 0.0) and at(0.0, 2.5)  # walls
    assert not at(*WORKER)  # the worker's blob
    assert at(6.0, 1.0)  # the first map's


def test_a_person_shown_standing_against_a_wall_is_not_taken_in_with_it():
    """A worker paused 5 cm from the east wall is one long component with it in SLAM's map; cut
    out where a person is shown, the wall is still structure and the worker is not."""
    walls, _ = scene()
    first = OccupancyMap(np.zeros_like(mapped(walls).occupancy), 0.05, -0.1, -0.1)
    worker = (7.7, 2.5)
    live = with_cells(mapped(walls), *worker, 0.15)
    g = live.geometry

    def at(taken, x, y):
        ix, iy = g.cell_of(x, y)
        return bool(taken[iy, ix])
    merged = first_and_structure(first, live)
    assert at(merged, *worker)  # the wall took the worker in
    floor = floor_seen(mapped(walls), None, None)  # the floor seen free before they stood there
    cut = without(live, [(*worker, 0.2)], PeopleConfig().margin, floor)
    taken = first_and_structure(first, live, structure=cut)
    assert not at(taken, *worker) and not at(taken, worker[0] + 0.12, worker[1])
    assert at(taken, 8.0, 2.5) and at(taken, 8.0, 1.0)  # the wall behind and beside them still is
    assert without(live, [], 0.1) is live
    # a false track on the wall itself cuts nothing of it: the wall was never floor
    on_wall = first_and_structure(first, live, without(live, [(8.0, 1.0, 0.2)], PeopleConfig().margin, floor))
    assert at(on_wall, 8.0, 1.0)


def test_the_rules_act_on_a_track_once_it_has_walked_and_on_while_it_stands():
    """A crouching worker (one block, no legs to see) is shown a person by walking."""
    walls, pots = scene()
    rig = Rig(mapped(walls), thing=lambda s: s.crouching(*WORKER, math.pi))
    rig.people.watch(pots, 0.10)
    rig.ticks(15)
    assert rig.people.current() and rig.people.confident() == ()  # a block standing there: not shown a person yet
    for k in range(25):  # walks 1 m east at 0.4 m/s
        s, _ = scene()
        s.crouching(WORKER[0] + 0.04 * (k + 1), WORKER[1], math.pi)
        rig.points = s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))
        rig.ticks(1)
    assert len(rig.people.confident()) == 1
    rig.ticks(20)  # stands again where it stopped
    (p,) = rig.people.confident()
    assert abs(p.x - (WORKER[0] + 1.0)) < 0.3 and math.hypot(p.vx, p.vy) == 0.0


def test_a_worker_standing_legs_apart_is_a_person_once_seen_as_a_pair_of_legs_on_a_few_scans():
    walls, pots = scene()
    rig = Rig(mapped(walls), heading=math.pi)  # facing the robot: both legs in view
    rig.people.watch(pots, 0.10)
    rig.ticks(LEGS_SEEN - 1)
    assert rig.people.current() and rig.people.confident() == ()  # one or two scans may be a fluke
    rig.ticks(1)
    (p,) = rig.people.confident()
    assert math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15


def test_a_box_seen_corner_on_where_the_worker_stood_is_never_a_pair_of_legs():
    walls, pots = scene()
    rig = Rig(mapped(walls), thing=lambda s: s.box(*WORKER, 0.3, 0.3, math.pi / 4))
    rig.people.watch(pots, 0.10)
    rig.ticks(20)
    assert rig.people.current() and rig.people.confident() == ()


def test_a_worker_standing_side_on_is_a_person_once_seen_as_a_leg_arc_scan_after_scan_and_a_moved_pot_never():
    walls, pots = scene()
    rig = Rig(mapped(walls))  # facing north, seen from the west: one leg hides the other
    rig.people.watch(pots, 0.10)
    rig.ticks(LEG_SCANS - 1)
    assert rig.people.current() and rig.people.confident() == ()
    rig.ticks(1)
    (p,) = rig.people.confident()
    assert math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15
    rig = Rig(mapped(walls), thing=lambda s: s.circles.append((*WORKER, POT_RADIUS)))  # a pot moved into the aisle
    rig.people.watch(pots, 0.10)
    for k in range(30):  # a fresh noisy scan each time
        s, _ = scene()
        s.circles.append((*WORKER, POT_RADIUS))
        rig.points = s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0), seed=k)
        rig.ticks(1)
    assert rig.people.current() and rig.people.confident() == ()


def test_someone_standing_in_the_first_map_is_not_explained_by_it_once_seen_gone():
    """A grower standing at the start of their round is in the first map; once SLAM sees the
    spot free, the first map stops explaining it, and they are tracked when they come back."""
    walls, pots = scene()
    first = with_cells(mapped(walls), *WORKER, 0.2)
    rig = Rig(first)  # side-on: one leg behind the other, no pair for stood_at_start to find
    rig.people.watch(pots, 0.10)
    assert rig.ticks(5) == ()  # explained by the first map: they were there at the start
    rig.map = with_cells(mapped(walls), *WORKER, 0.3, value=0)  # they walked off: SLAM saw the spot free
    rig.ticks(1)
    rig.map = with_cells(mapped(walls), *WORKER, 0.2)  # and came back
    people = rig.ticks(5)
    assert len(people) == 1 and math.hypot(people[0].x - WORKER[0], people[0].y - WORKER[1]) < 0.15
    legs = np.hypot(rig.points[:, 0] - WORKER[0], rig.points[:, 1] - WORKER[1]) < 0.3
    assert not rig.people.scene.explained(rig.points)[legs].any()


def test_someone_standing_in_the_first_map_all_along_is_found_by_their_legs_and_a_crate_there_never():
    """A grower who stood on their spot when the first map was made, and never leaves it: the
    leg pass on what only the first map explains finds their legs (``stood_at_start``), the map
    stops explaining them, and they are a person by their legs as anyone. A crate the first map
    holds stays the greenhouse's."""
    walls, pots = scene()
    first = with_cells(mapped(walls), *WORKER, 0.2)
    rig = Rig(first, heading=math.pi)  # facing the robot: both legs in view
    rig.people.watch(pots, 0.10)
    scans = SEEN
    assert rig.ticks(scans - 1) == ()  # explained until the pass saw their legs on SEEN scans
    rig.ticks(1 + LEGS_SEEN)
    (p,) = rig.people.confident()
    assert math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15
    legs = np.hypot(rig.points[:, 0] - WORKER[0], rig.points[:, 1] - WORKER[1]) < 0.3
    assert not rig.people.scene.explained(rig.points)[legs].any()
    rig = Rig(with_cells(mapped(walls), *WORKER, 0.25), thing=lambda s: s.box(*WORKER, 0.3, 0.3, math.pi / 4))
    rig.people.watch(pots, 0.10)
    assert rig.ticks(10 * scans) == ()


def test_the_spots_of_legs_are_counted_per_place_and_forgotten_when_not_seen_again():
    stood = StoodAtStart()
    assert stood.found(0.0, np.array([[1.0, 1.0], [3.0, 1.0]])) == []
    assert stood.found(0.3, np.array([[1.05, 1.0]])) == []
    assert stood.found(0.6 + FORGET, np.array([[1.0, 1.02], [3.0, 1.0]])) == []  # both forgotten by then
    assert stood.found(0.9 + FORGET, np.array([[1.0, 1.0], [3.0, 1.0]])) == []
    assert stood.found(1.2 + FORGET, np.array([[1.0, 1.0]])) == [(1.0, 1.0)]
    assert stood.found(1.5 + FORGET, np.array([[1.0, 1.0]])) == []  # counted afresh once cleared
    left = np.zeros((40, 40), bool)
    clear_round(left, GridGeometry(0.05, 0.0, 0.0, 40, 40), [(1.0, 1.0)])
    assert left[20, 20] and left[20, 20 + int(REACH / 0.05)] and not left[20, 20 + int(REACH / 0.05) + 2]


def test_a_person_lost_for_a_moment_is_a_person_again_at_once_where_they_were_lost():
    walls, pots = scene()
    rig = Rig(mapped(walls), thing=lambda s: s.crouching(*WORKER, math.pi))
    rig.people.watch(pots, 0.10)
    for k in range(25):  # a crouching worker shuffles 1 m east: a person by walking
        s, _ = scene()
        s.crouching(WORKER[0] + 0.04 * (k + 1), WORKER[1], math.pi)
        rig.points = s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))
        rig.ticks(1)
    (before,) = rig.people.confident()
    seen = rig.points
    rig.points = scene()[0].scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))  # hidden for 1.5 s: the track dies
    rig.ticks(15)
    assert rig.people.current() == ()
    rig.points = seen
    rig.ticks(1)
    (after,) = rig.people.confident()
    assert after.id == before.id  # them again, under their id
    rig.points = scene()[0].scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))
    rig.ticks(50)  # gone for 5 s: forgotten
    rig.points = seen
    rig.ticks(1)
    assert rig.people.current() and rig.people.confident() == ()


def test_a_person_shown_is_cut_from_the_structure_as_wide_as_their_track_ever_was_and_where_lost_for_a_while():
    """A cart paused against a wall is one long component with it; its track, cut out by its own
    shrinking radius, died. A person shown is cut as wide as their track has been, and where one
    was lost too, for ``LOST_KEEP`` seconds."""
    walls, pots = scene()
    rig = Rig(mapped(walls), thing=lambda s: s.crouching(*WORKER, math.pi))
    rig.people.watch(pots, 0.10)
    for k in range(25):  # shown a person by walking 1 m east
        s, _ = scene()
        s.crouching(WORKER[0] + 0.04 * (k + 1), WORKER[1], math.pi)
        rig.points = s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))
        rig.ticks(1)
    (p,) = rig.people.confident()
    widest = rig.people._widest[p.id]
    assert widest >= p.radius and [r for x, y, r in rig.people._tracked_in_map()] == [widest]
    rig.points = scene()[0].scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))  # the map took them in: lost
    rig.ticks(int(LOST_KEEP * 10) - 5)
    assert rig.people.current() == ()
    (spot,) = rig.people._tracked_in_map()
    assert math.hypot(spot[0] - p.x, spot[1] - p.y) < 0.3 and spot[2] >= widest  # where it last was, coasting
    rig.ticks(10)
    assert rig.people._tracked_in_map() == []


def test_a_tracker_that_fails_on_a_scan_is_logged_and_drops_its_people_without_raising(caplog):
    walls, pots = scene()
    rig = Rig(mapped(walls), heading=math.pi)
    rig.people.watch(pots, 0.10)
    assert rig.ticks(5)

    def broken(*args):
        raise np.linalg.LinAlgError("Singular matrix")

    rig.people.tracker.update = broken
    with caplog.at_level("ERROR", logger="lupin"):
        assert rig.ticks(3) == ()
    assert rig.people.failures == 3
    assert sum("person tracker failed" in r.message for r in caplog.records) == 1  # once a minute, not per scan


def test_a_track_where_another_robot_of_the_fleet_says_it_stands_is_that_robot_not_a_person():
    """Another robot's lidar puck and arm look like a pair of legs: a track within ROBOT_REACH of
    where a fleet's robot says it is (map frame, over the link) is never shown a person."""
    walls, pots = scene()
    rig = Rig(mapped(walls), heading=math.pi)  # a pair of legs in view, as the other robot's would be
    rig.people.watch(pots, 0.10)
    rig.people.robots = lambda: [Pose2D(WORKER[0] + 0.2, WORKER[1], 0.0)]
    rig.ticks(LEGS_SEEN + 3)
    assert rig.people.current() and rig.people.confident() == ()
    rig.people.robots = lambda: [Pose2D(WORKER[0] + 1.0, WORKER[1], 0.0)]  # that robot is elsewhere: a person
    rig.ticks(1)
    (p,) = rig.people.confident()
    assert math.hypot(p.x - WORKER[0], p.y - WORKER[1]) < 0.15


def test_where_the_fleet_says_a_robot_stands_is_taken_from_the_map_into_odom():
    """The robots are told in the map frame and the tracks live in odom: ``map_to_odom`` takes
    odom into the map, so a told pose goes back through its inverse (composed the other way, a
    robot 0.2 m of SLAM correction off its odometry placed the others 0.4 m from where they were)."""
    walls, _ = scene()
    m2o = Pose2D(0.3, -0.2, 0.4)
    people = People(PeopleConfig(), lambda: None, lambda: ODOM, MOUNT, lambda: m2o, lambda: mapped(walls),
                    lambda: CHASSIS, 0.02)
    seen_at = Pose2D(2.0, 1.0, 0.0)  # odom
    told = compose(m2o, seen_at)  # the same place, map frame
    people.robots = lambda: [told]
    ((x, y),) = people._robots_in_odom()
    assert math.hypot(x - seen_at.x, y - seen_at.y) < 1e-9


def test_a_thing_beside_a_person_whose_track_is_lost_is_that_person_not_nobody():
    """A cart and its pusher seen as two bodies: the person's track dies (it hopped onto the legs,
    say) while the cart's, never shown a person, stays. The cart is taken for them, under their
    id; it was nobody, and the robot drove up to 0.13 m of a cart whose grower waited for it."""
    walls, pots = scene()

    def scan(k: int | None):
        s, _ = scene()
        s.box(4.3, 3.0, 0.3, 0.3)  # beside where the worker stops, apart enough to be a body of its own
        if k is not None:
            s.crouching(WORKER[0] + 0.04 * (k + 1), WORKER[1], math.pi)
        return s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))

    rig = Rig(mapped(walls), thing=lambda s: s.crouching(*WORKER, math.pi))
    rig.people.watch(pots, 0.10)
    for k in range(25):  # a crouching worker shuffles 1 m east: a person by walking
        rig.points = scan(k)
        rig.ticks(1)
    (worker,) = rig.people.confident()
    (box,) = [p for p in rig.people.current() if p.id != worker.id]
    assert math.hypot(box.x - worker.x, box.y - worker.y) < 0.8  # near, but a track of its own, not shown
    rig.points = scan(None)
    rig.ticks(15)  # the worker's track dies
    (now,) = rig.people.current()
    assert rig.people.confident() == (now,) and now.id == worker.id and math.hypot(now.x - box.x, now.y - box.y) < 0.1


def test_a_thing_where_a_person_stood_still_is_a_person_once_their_track_walks_off():
    """A cart pusher paused at the end of their aisle, and a grower walking past drew the track
    off onto themselves; the cart stayed a track never shown a person, and the robot drove along
    it at 0.08 m (safety.people seed 1, 274-282 s). Here the worker walks off and leaves the box:
    the box is a person from then on, and the worker goes on under their id."""
    walls, pots = scene()
    stop = (WORKER[0] + 0.6, WORKER[1])

    def scan(x: float):
        s, _ = scene()
        s.box(stop[0] + 0.3, 3.0, 0.3, 0.3)  # beside where the worker stops, a body of its own
        s.crouching(x, WORKER[1], math.pi)
        return s.scan((ODOM.x + MOUNT.x, ODOM.y + MOUNT.y, 0.0))

    rig = Rig(mapped(walls), thing=lambda s: s.crouching(*WORKER, math.pi))
    rig.people.watch(pots, 0.10)
    for k in range(15):  # shuffles 0.6 m east: a person by walking
        rig.points = scan(WORKER[0] + 0.04 * (k + 1))
        rig.ticks(1)
    rig.ticks(20)  # and stands
    (worker,) = rig.people.confident()
    (box,) = [p for p in rig.people.current() if p.id != worker.id]
    assert not any(p.id == box.id for p in rig.people.confident())
    for k in range(20):  # walks off east at 0.8 m/s, past the box and the reach of where they stood
        rig.points = scan(stop[0] + 0.08 * (k + 1))
        rig.ticks(1)
    shown = {p.id: p for p in rig.people.confident()}
    assert worker.id in shown and math.hypot(shown[worker.id].x - stop[0], shown[worker.id].y - stop[1]) > 0.8
    assert [p for p in shown.values() if p.id != worker.id and math.hypot(p.x - box.x, p.y - box.y) < 0.1]
