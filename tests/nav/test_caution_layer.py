"""The caution layer (issue 28 item 2): round a thing the map explains but cannot tell from
someone (a worker crouching against a divider since before the patrol), a person's passing berth
priced but never a wall; a plan keeps it where the aisle has room and still reaches a pose
beside the thing."""
from __future__ import annotations

import numpy as np

from hw.people import Person
from nav.config import NavConfig
from nav.costmap.grid import INSCRIBED
from nav.costmap.layered import global_costmap
from nav.planner import NavfnPlanner

CFG = NavConfig()
R = CFG.costmap.robot_radius
CROUCHING = Person(id=7, x=0.0, y=0.0, vx=0.05, vy=-0.04, radius=0.25, confidence=0.5)


def _open(things=(), people=()):
    cm = global_costmap(CFG.costmap, lambda: list(people), things=lambda: list(things))
    cm.set_static(np.zeros((120, 120), np.int8), 0.05, -3.0, -3.0)  # open, explored floor
    return cm


def cost(cm, x, y) -> int:
    return int(cm.grid.cost_at(np.array([x]), np.array([y]))[0])


def test_a_thing_is_priced_to_a_persons_clearance_never_inscribed_and_the_same_all_round():
    cm = _open([CROUCHING])
    edge = CROUCHING.radius + R  # the robot's body touching the thing's
    near, mid, far = (cost(cm, edge + g, 0.0) for g in (0.03, 0.15, 0.27))
    assert INSCRIBED > near > mid > far > 0
    assert cost(cm, edge + 0.35, 0.0) == 0  # past the 0.3 m berth: free
    assert abs(cost(cm, 0.0, -(edge + 0.15)) - mid) <= 10  # still: its velocity jitter draws no stretch
    assert cost(_open(), edge + 0.03, 0.0) == 0


def test_people_are_not_things_and_a_thing_takes_nothing_from_the_person_layer():
    walker = Person(id=8, x=0.0, y=0.0, vx=0.0, vy=0.0, radius=0.25, confidence=0.9)
    both = _open([CROUCHING], [walker])
    assert cost(both, CROUCHING.radius + R + 0.2, 0.0) >= INSCRIBED  # the person's keep-out stands


def test_a_plan_past_a_thing_in_a_wide_aisle_keeps_the_berth_and_one_to_it_arrives():
    """A 1.9 m cross aisle (walls at y = +-0.95) with a crouching worker 0.4 m off its north
    wall: the plan along the aisle passes them 0.3 m body to body; a goal beside them is still
    reached."""
    occupancy = np.zeros((120, 120), np.int8)
    rows = (np.arange(120) * 0.05 - 3.0 + 0.025)
    occupancy[np.abs(rows) >= 0.95, :] = 100
    worker = Person(id=9, x=0.0, y=0.95 - 0.4, vx=0.0, vy=0.0, radius=0.25, confidence=0.5)
    planner = NavfnPlanner(CFG.planner)
    for things, least in (([], 0.0), ([worker], 0.27)):
        cm = global_costmap(CFG.costmap, things=lambda things=things: things)
        cm.set_static(occupancy, 0.05, -3.0, -3.0)
        path = planner.plan(cm.grid, (-2.5, 0.0), (2.5, 0.0))
        gap = float(np.min(np.hypot(path[:, 0] - worker.x, path[:, 1] - worker.y))) - worker.radius - R
        assert gap >= least
        if not things:
            assert gap < 0.25  # without the layer the plan skims them: the layer is what keeps off
    beside = planner.plan(cm.grid, (-2.5, 0.0), (worker.x + worker.radius + R + 0.1, worker.y))
    assert np.hypot(*(beside[-1] - [worker.x + worker.radius + R + 0.1, worker.y])) < 0.1
