"""Generated worlds (spec/world.md, `lupin sim generate`): valid, deterministic, the default's
layout, and a clear refusal of impossible sizes."""
from __future__ import annotations

import math

import pytest

from hw.errors import InputError
from sim.generate import LEAF_PEST_POTS, MAX_ROWS, generate_world
from sim.world import ROBOT_RADIUS, Pose2, World, dump_world, load_default_world, load_world, world_problems

SIZES = [(1, 1, 0), (1, 2, 1), (1, 3, 2), (2, 5, 3), (3, 4, 7), (4, 3, 8), (6, 10, 11), (14, 40, 5)]


def _inspection_poses(world: World, standoff: float = 0.5) -> list[Pose2]:
    """Where the robot stands to inspect each pot: 0.5 m out along its facing (the aisle centre)."""
    return [
        Pose2(x=p.x + standoff * math.cos(p.facing), y=p.y + standoff * math.sin(p.facing),
              yaw=p.facing + math.pi)
        for p in world.pots
    ]


@pytest.mark.parametrize(("rows", "per_row", "seed"), SIZES)
def test_generated_world_round_trips_and_validates(tmp_path, rows, per_row, seed):
    world = generate_world(rows, per_row, seed)
    assert world_problems(world) == []
    path = tmp_path / "gen.yaml"
    path.write_text(dump_world(world))
    assert load_world(path) == world


@pytest.mark.parametrize(("rows", "per_row", "seed"), SIZES)
def test_generated_world_content(rows, per_row, seed):
    world = generate_world(rows, per_row, seed)
    n = rows * per_row
    assert len(world.pots) == n
    assert len({p.id for p in world.pots}) == n
    assert [p.tag for p in world.pots] == list(range(1, n + 1))
    assert all(1 <= p.blooms <= 3 for p in world.pots)
    assert set(world.climate) == {p.tag for p in world.pots}
    if n >= 3:
        assert any(p.flower == "none" for p in world.pots)
        assert any(p.bug for p in world.pots)
        assert any(p.bug and p.flower != "none" for p in world.pots)
    if n >= LEAF_PEST_POTS:
        assert any(p.bug and p.flower == "none" for p in world.pots), "a pest on a plant with no bloom"
    if n >= 4:
        assert {"red", "white", "pink"} <= {p.flower for p in world.pots}


@pytest.mark.parametrize(("rows", "per_row", "seed"), SIZES)
def test_generated_layout_has_aisles(rows, per_row, seed):
    world = generate_world(rows, per_row, seed)
    r = 0.10
    xs = [p.x for p in world.pots]
    assert min(xs) - r >= 1.5, "west cross aisle"
    assert world.floor.x - (max(xs) + r) >= 1.5, "east cross aisle"
    assert min(p.y for p in world.pots) - r >= 0.9, "south aisle"
    row_ys = sorted({p.y for p in world.pots})
    assert len(row_ys) == rows
    for a, b in zip(row_ys, row_ys[1:]):
        assert b - a - 2 * r == pytest.approx(0.8), "~0.8 m aisles"
    for i, y in enumerate(row_ys):  # first row faces south; then pairs face the aisle between them
        want = -math.pi / 2 if i % 2 == 0 else math.pi / 2
        assert all(p.facing == want for p in world.pots if p.y == y)
    assert (world.spawn.x, world.spawn.y) == (1.0, 0.5)
    assert world.spawn.y < row_ys[0] - r - ROBOT_RADIUS
    # The robot fits at every inspection pose: put the spawn there and re-check the geometry.
    for pose in _inspection_poses(world):
        assert world_problems(world.model_copy(update={"spawn": pose})) == []


def test_default_world_inspection_poses_are_clear():
    world = load_default_world()
    for pose in _inspection_poses(world):
        assert world_problems(world.model_copy(update={"spawn": pose})) == []


def test_three_by_four_has_the_default_layout():
    gen, default = generate_world(3, 4, seed=0), load_default_world()
    assert gen.floor == default.floor and gen.spawn == default.spawn
    for g, d in zip(gen.pots, default.pots):
        assert g.id == d.id and g.tag == d.tag and g.y == d.y
        assert g.x == pytest.approx(d.x, abs=0.05)
        assert g.facing == pytest.approx(d.facing, abs=1e-4)


def test_same_seed_same_world_other_seed_other_world():
    assert dump_world(generate_world(4, 6, 42)) == dump_world(generate_world(4, 6, 42))
    assert generate_world(4, 6, 42) != generate_world(4, 6, 43)


def test_jitter_is_small_and_seeded():
    world = generate_world(2, 8, 3)
    offsets = [p.x - (2.0 + i % 8) for i, p in enumerate(world.pots)]
    assert all(abs(o) <= 0.05 for o in offsets)
    assert any(abs(o) > 0.001 for o in offsets)


def test_name():
    assert generate_world(2, 3, 9).name == "generated-2x3-seed9"
    assert generate_world(2, 3, 9, name="bench").name == "bench"


@pytest.mark.parametrize(
    ("rows", "per_row", "text"),
    [
        (0, 3, "rows must be a whole number from 1 to 40 (got 0)"),
        (MAX_ROWS + 1, 3, "rows must be a whole number from 1 to 40 (got 41)"),
        (3, 0, "pots per row must be a whole number from 1 to 40 (got 0)"),
        (3, 41, "pots per row must be a whole number from 1 to 40 (got 41)"),
        (-2, 3, "rows"),
        (2.5, 3, "rows"),
        (True, 3, "rows"),
        (20, 30, "600 pots"),
        (40, 40, "1600 pots"),
    ],
)
def test_impossible_sizes_are_refused(rows, per_row, text):
    with pytest.raises(InputError) as info:
        generate_world(rows, per_row, 0)
    assert text in str(info.value)


def _inside(x: float, y: float, box) -> bool:
    return abs(x - box.x) <= box.sx / 2 and abs(y - box.y) <= box.sy / 2


@pytest.mark.parametrize(("bays", "rows", "per_row"), [(2, 6, 15), (3, 2, 4), (4, 14, 3)])
def test_bays_stand_side_by_side_behind_dividers_with_doorways(tmp_path, bays, rows, per_row):
    world = generate_world(rows, per_row, 4, bays=bays)
    assert world_problems(world) == [] and len(world.pots) == bays * rows * per_row
    one = generate_world(rows, per_row, 4)
    length = one.floor.x
    assert world.floor.x == pytest.approx(bays * length) and world.floor.y == one.floor.y
    for b in range(bays):  # each bay has the one-bay layout, shifted east
        xs = sorted(p.x for p in world.pots if b * length < p.x < (b + 1) * length)
        assert len(xs) == rows * per_row and xs[0] - b * length >= 1.5 and (b + 1) * length - xs[-1] >= 1.5
    walls = {round(o.x, 6) for o in world.obstacles}
    assert walls == {round(b * length, 6) for b in range(1, bays)}
    ys = [k * 0.05 for k in range(int(world.floor.y / 0.05) + 1)]
    for x in walls:
        wall = [o for o in world.obstacles if round(o.x, 6) == x]
        assert all(o.h == 2.0 and o.sx == 0.1 for o in wall)
        open_ = [y for y in ys if not any(_inside(x, y, o) for o in wall)]
        assert open_[0] < 0.3 and open_[-1] > world.floor.y - 0.3  # a doorway at each end
        runs, start = [], open_[0]  # doorways: runs of open y, each wide enough for the robot
        for a, b in zip(open_, open_[1:] + [None]):
            if b is None or b - a > 0.051:
                runs.append((start, a))
                start = b
        assert all(hi - lo >= 1.1 for lo, hi in runs)
        centres = [(lo + hi) / 2 for lo, hi in runs]  # never more than 6 m along the wall to a doorway
        assert max(b - a for a, b in zip(centres, centres[1:])) <= 6.0 + 0.05
    path = tmp_path / "bays.yaml"
    path.write_text(dump_world(world))
    assert load_world(path) == world and world.name == f"generated-{bays}bays-{rows}x{per_row}-seed4"


def test_too_many_bays_or_pots_are_refused():
    with pytest.raises(InputError, match="bays must be a whole number from 1 to 10"):
        generate_world(2, 2, 0, bays=11)
    with pytest.raises(InputError, match="3 bays x 10 rows x 20 pots = 600 pots"):
        generate_world(10, 20, 0, bays=3)
