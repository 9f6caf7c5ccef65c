"""Generated greenhouse worlds for `lupin sim generate` (spec/world.md, spec/cli.md).

The layout repeats the built-in greenhouse (sim/worlds/default.yaml), so
``generate_world(3, 4, seed)`` has the default's floor, rows and aisles:

- pots 1.0 m apart along x, the first at x = 2.0, each jittered by up to a few cm (seeded);
- rows 1.0 m apart from y = 1.0, which leaves 0.8 m between pot edges: the spec's ~0.8 m
  aisles; the south aisle (below the first row) is 0.9 m wide and so is the north strip;
- the first row faces the south aisle; after it, rows pair up around the aisle between them
  (row 1 faces north, row 2 south, row 3 north, ...), so a robot inspects two rows per aisle;
- open cross aisles of 1.9 m (>= 1.5 m even with jitter) at both ends for turning;
- spawn at the west end of the south aisle, looking east.

With ``bays`` > 1 (a commercial greenhouse's layout), that bay repeats eastwards, the bays side
by side along the rows, each behind a divider wall (a 0.1 m thick, 2 m tall box across the whole
floor standing in the middle of the 3.8 m between two bays' pot rows) with a 1.2 m doorway at the south end,
one at the north end and one every ``DOOR_SPACING`` metres between: the robot crosses from bay
to bay through the cross aisles, so a long greenhouse is also a test of planning through
doorways and of SLAM in rooms joined by narrow gaps.

With ``walkers`` K, K people share the greenhouse in the mix ``ROLES`` cycles through (issue 28:
the figures must not rest on polite walkers), a third of everyone with ``yields: false``:

- people and cart pushers who yield work an aisle between two rows (or the north aisle; never
  the south aisle the robot starts in, so no one stands on the spawn), one per aisle, walking it
  from the row's first pot to its last at a seeded speed, with a pause at each end and a
  staggered start;
- those who do not yield walk through the house along a cross aisle (the west or east end of a
  bay), across the mouths of the aisles the robot works from: someone looking at the plants, not
  at the robot, crossing its path. Not down an aisle: pacing a 0.8 m aisle end to end for ever,
  never yielding, would leave the robot no moment in which it may be there by the issue's own
  rules (0.3 m body to body), so that aisle's pots would measure the world, not the robot;
- workers who stay put (standing, or crouching at a bench) are at the east end of their aisle,
  ``WORKER_FROM_WALL`` from the wall, where the robot must pass them in the cross aisle.

Each pot gets a unique tag (1, 2, 3, ...: AprilTag 36h11 has ids 0..586, so at most 586
pots), a seeded flower colour, 1..3 blooms and a climate reading; with 3 or more pots at least
one pot has no bloom (``none``) and at least one has a pest (``bug``), as the spec asks ("some
none, some bug"); from ``LEAF_PEST_POTS`` pots on, a pot with no bloom has a pest too (its pest
is on a leaf, spec/world.md; the sim puts some flowering plants' pests on a leaf as well,
``sim.pests``). Same arguments, same world: every draw comes from ``random.Random(seed)`` (the
pests of plants with no bloom from their own stream, so adding them moved no pot).
"""
from __future__ import annotations

import math
import random

from hw.errors import InputError
from hw.tag_family import TAG_IDS
from sim.world import Climate, Floor, Obstacle, Pose2, Pot, Walker, World, validate_world, world_problems

MAX_ROWS = 40
"""Largest --rows (and --pots-per-row) accepted: a 40 x 40 m greenhouse is already far beyond
anything a patrol covers in one battery charge."""

POT_PITCH = 1.0
"""Pot centre spacing along a row, m (default world)."""
ROW_PITCH = 1.0
"""Row centre spacing, m: 0.8 m aisle + two 0.10 m pot radii (spec: aisles about 0.8 m)."""
FIRST_POT_X = 2.0
"""x of a row's first pot, m: 1.9 m of west cross aisle beyond its edge."""
FIRST_ROW_Y = 1.0
"""y of the first row, m: a 0.9 m south aisle below its pot edges."""
END_MARGIN = 2.0
"""From the last pot's centre to the east wall, m: a 1.9 m east cross aisle."""
NORTH_MARGIN = 1.0
"""From the last row's centre to the north wall, m: a 0.9 m north aisle."""
JITTER = 0.03
"""Largest seeded x offset of a pot, m: pots never touch (1.0 m pitch) and the cross aisles
stay >= 1.5 m wide."""
SPAWN = (1.0, 0.5, 0.0)
"""Robot start (x, y, yaw): the west end of the south aisle, looking east along it."""
MAX_ROBOTS = 9
"""Largest --robots accepted: the console switches robots with the keys 1..9 (spec/fleet.md)."""

MAX_BAYS = 10
"""Largest --bays accepted (ten 16 m bays: a 160 m greenhouse)."""
DIVIDER_THICKNESS, DIVIDER_HEIGHT = 0.1, 2.0
"""A bay divider, m: a thin wall as tall as the outer walls."""
DOOR_WIDTH = 1.2
"""A doorway in a divider, m: the 0.44 m robot with its 0.25 m inflation on both sides and room
to spare (a greenhouse door for carts is 1.2-1.5 m)."""
DOOR_SPACING = 6.0
"""Most a robot walks along a divider to reach a doorway, m: doorways at both ends and at least
every this many metres between."""

LEAF_PEST_POTS = 10
"""From this many pots, a pot with no bloom has a pest too (about one in three of them, at least
one): a greenhouse of a dozen pots already shows a pest on a plant with no bloom."""

MAX_WALKERS = 50
"""Largest --walkers accepted."""
WALKER_SPEED = (0.6, 1.2)
"""Seeded walking speed range, m/s (a grower at work, not hurrying)."""
WALKER_PAUSE = (2.0, 8.0)
"""Seeded standing time at each end of the aisle, s."""
WALKER_START = 30.0
"""Latest seeded start, s."""
CART_WIDTH = 0.7
"""A generated cart pusher's width, m: a cart (over 0.6) that still fits a 0.8 m aisle between
pot edges with 5 cm to spare each side."""
WORKER_FROM_WALL = 0.4
"""A worker who stays put stands this far from the east wall (or divider) of the bay, m: at a
bench against the wall, leaving the 1.9 m cross aisle room to pass them at arm's length."""
ROLES = (("walking", False), ("standing", True), ("cart", True), ("crouching", True), ("walking", True),
         ("cart", False))
"""The mix ``--walkers K`` cycles through, (role, yields): of every six, two walk, two push a
cart, one stands and one crouches at a bench, and two (a third) do not yield. The order puts
one of each kind but the yielding walker in the first four."""

_SOUTH, _NORTH = -math.pi / 2, math.pi / 2


def generate_world(rows: int, pots_per_row: int, seed: int, name: str | None = None, bays: int = 1,
                   walkers: int = 0, robots: int = 1) -> World:
    """A valid world of ``bays`` x ``rows`` x ``pots_per_row`` pots, the same for the same arguments;
    with ``robots`` > 1, a dock for each (``spawns``, ``_docks``).

    Raises :class:`InputError` for sizes outside 1..40 (bays 1..10, robots 1..9 and at most one
    per aisle) or more pots than there are tag ids.
    """
    for option, value, least, most in (("rows", rows, 1, MAX_ROWS), ("pots per row", pots_per_row, 1, MAX_ROWS),
                                       ("bays", bays, 1, MAX_BAYS), ("walkers", walkers, 0, MAX_WALKERS),
                                       ("robots", robots, 1, MAX_ROBOTS)):
        if isinstance(value, bool) or not isinstance(value, int) or not least <= value <= most:
            raise InputError(f"{option} must be a whole number from {least} to {most} (got {value!r})")
    if robots > rows + 1:
        raise InputError(f"--robots {robots}: {robots} robots need {robots} docks, one at the west end of each aisle, and "
                         f"{rows} rows leave {rows + 1} aisles; generate more rows or fewer robots")
    count = bays * rows * pots_per_row
    max_pots = len(TAG_IDS) - 1  # tags start at 1
    if count > max_pots:
        bay_text = f"{bays} bays x " if bays > 1 else ""
        raise InputError(
            f"{bay_text}{rows} rows x {pots_per_row} pots = {count} pots, but every pot needs its own "
            f"AprilTag 36h11 id and there are only {max_pots} (ids 1..{TAG_IDS[-1]}); generate fewer pots"
        )
    rng = random.Random(seed)
    flowers, bugs = _flower_mix(count, rng)
    _leaf_pests(flowers, bugs, random.Random(f"{seed}-pests"))
    width = max(2, len(str(count)))
    pots: list[Pot] = []
    climate: dict[int, Climate] = {}
    bay_length = FIRST_POT_X + (pots_per_row - 1) * POT_PITCH + END_MARGIN
    for bay, row in ((b, r) for b in range(bays) for r in range(rows)):
        facing = _SOUTH if row % 2 == 0 else _NORTH
        for col in range(pots_per_row):
            k = len(pots)
            tag = k + 1
            pots.append(Pot(
                id=f"P{tag:0{width}d}",
                x=round(bay * bay_length + FIRST_POT_X + col * POT_PITCH + rng.uniform(-JITTER, JITTER), 3),
                y=FIRST_ROW_Y + row * ROW_PITCH,
                facing=facing,
                tag=tag,
                flower=flowers[k],
                bug=bugs[k],
                blooms=1 if flowers[k] == "none" else rng.randint(1, 3),
            ))
            climate[tag] = _climate(rng)
    floor_y = FIRST_ROW_Y + (rows - 1) * ROW_PITCH + NORTH_MARGIN
    world = World(
        name=name or (f"generated-{rows}x{pots_per_row}-seed{seed}" if bays == 1
                      else f"generated-{bays}bays-{rows}x{pots_per_row}-seed{seed}"),
        floor=Floor(x=bays * bay_length, y=floor_y),
        spawn=Pose2(x=SPAWN[0], y=SPAWN[1], yaw=SPAWN[2]),
        spawns=_docks(robots),
        pots=pots,
        obstacles=[box for b in range(1, bays) for box in _divider(b * bay_length, floor_y)],
        walkers=_walkers(walkers, rows, bays, bay_length, pots_per_row, floor_y, random.Random(f"{seed}-walkers")),
        climate=climate,
    )
    validate_world(world, source=f"generated world {world.name!r}")  # a failure here is a bug
    return world


def _docks(robots: int) -> list[Pose2]:
    """A fleet's docks: the spawn, then one at the west end of each next aisle northwards, each
    looking east along its aisle (1 m apart in the 1.9 m west cross aisle, clear of the rows);
    none for one robot (its world file stays as before)."""
    if robots == 1:
        return []
    return [Pose2(x=SPAWN[0], y=SPAWN[1] + k * ROW_PITCH, yaw=SPAWN[2]) for k in range(robots)]


def _walkers(count: int, rows: int, bays: int, bay_length: float, pots_per_row: int, floor_y: float,
             rng: random.Random) -> list[Walker]:
    """``count`` people in the module docstring's places, each in its own aisle or cross aisle
    (people do not walk through each other, and two pacing one 0.8 m aisle would close it for
    good); its own random stream, so adding walkers never changes the pots."""
    aisles = [FIRST_ROW_Y + (r + 0.5) * ROW_PITCH for r in range(rows - 1)]
    aisles.append(round((FIRST_ROW_Y + (rows - 1) * ROW_PITCH + floor_y) / 2, 3))  # the north aisle
    roles = [ROLES[k % len(ROLES)] for k in range(count)]
    crossing = sum(not yields for _, yields in roles)
    slots = [(bay, y) for bay in range(bays) for y in aisles]
    ends = [(bay, side) for bay in range(bays) for side in ("west", "east")]
    if count - crossing > len(slots) or crossing > len(ends):
        raise InputError(f"at most {len(slots) + len(ends)} walkers in {bays} bay(s) of {rows} rows: one per "
                         f"aisle or cross aisle, and at most {len(ends)} who do not yield (got {count})")
    in_aisle, in_cross = iter(rng.sample(slots, count - crossing)), iter(rng.sample(ends, crossing))
    out = []
    for k, (role, yields) in enumerate(roles):
        speed, pause, start = (round(rng.uniform(*WALKER_SPEED), 2), round(rng.uniform(*WALKER_PAUSE), 1),
                               round(rng.uniform(0.0, WALKER_START), 1))  # drawn for every role: a stable stream
        width = CART_WIDTH if role == "cart" else 0.45
        if not yields:
            bay, side = next(in_cross)
            x = _cross_aisle_x(bay, side, bay_length, pots_per_row)
            south = min(aisles[0] + ROW_PITCH / 2, aisles[-1])  # a cart ahead of them stays clear of the spawn
            path = [[x, south], [x, aisles[-1]]] if south < aisles[-1] else [[x, south]]  # one row: no way along
            out.append(Walker(id=f"W{k + 1}", path=path, speed=speed, pause=pause,
                              start=start, yields=False, width=width))
            continue
        bay, y = next(in_aisle)
        if role in ("standing", "crouching"):
            out.append(Walker(id=f"W{k + 1}", path=[[round((bay + 1) * bay_length - WORKER_FROM_WALL, 3), y]],
                              posture=role))
            continue
        x0 = bay * bay_length + FIRST_POT_X
        x1 = x0 + (pots_per_row - 1) * POT_PITCH
        out.append(Walker(id=f"W{k + 1}", path=[[round(x0, 3), y], [round(x1, 3), y]], speed=speed, pause=pause,
                          start=start, width=width))
    return out


def _cross_aisle_x(bay: int, side: str, bay_length: float, pots_per_row: int) -> float:
    """The middle of a bay's west cross aisle (between its wall or divider and its first pot) or
    east one (between its last pot and the next wall or divider)."""
    west = bay * bay_length
    if side == "west":
        return round(west + FIRST_POT_X / 2, 3)
    last = west + FIRST_POT_X + (pots_per_row - 1) * POT_PITCH
    return round((last + (bay + 1) * bay_length) / 2, 3)


def _divider(x: float, floor_y: float) -> list[Obstacle]:
    """The wall across the floor at ``x``, as boxes between its doorways: one doorway at each
    end of the wall and evenly spaced ones between, no two more than ``DOOR_SPACING`` apart."""
    gaps = max(1, math.ceil((floor_y - DOOR_WIDTH) / DOOR_SPACING))  # spacing between first and last doorway
    doors = [DOOR_WIDTH / 2 + k * (floor_y - DOOR_WIDTH) / gaps for k in range(gaps + 1)]
    edges = [0.0] + [e for c in doors for e in (c - DOOR_WIDTH / 2, c + DOOR_WIDTH / 2)] + [floor_y]
    segments = [(a, b) for a, b in zip(edges[::2], edges[1::2]) if b - a > 1e-6]
    return [Obstacle(x=x, y=round((a + b) / 2, 4), sx=DIVIDER_THICKNESS, sy=round(b - a, 4), h=DIVIDER_HEIGHT)
            for a, b in segments]


def _flower_mix(count: int, rng: random.Random) -> tuple[list[str], list[bool]]:
    """Colours and pests for ``count`` pots.

    About one pot in ten (at least one from 3 pots up) has no bloom; the others cycle red,
    white, pink before the shuffle, so every colour appears once 4 or more pots flower. About
    one flowering pot in ten (at least one, from 3 pots up) has a pest.
    """
    nones = max(1, count // 10) if count >= 3 else 0
    flowers = ["none"] * nones + [("red", "white", "pink")[k % 3] for k in range(count - nones)]
    rng.shuffle(flowers)
    bugs = [False] * count
    if count >= 3:
        flowering = [k for k in range(count) if flowers[k] != "none"]
        for k in rng.sample(flowering, max(1, len(flowering) // 10)):
            bugs[k] = True
    return flowers, bugs


def _leaf_pests(flowers: list[str], bugs: list[bool], rng: random.Random) -> None:
    """From ``LEAF_PEST_POTS`` pots on, about one pot in three with no bloom (at least one) gets a
    pest, in place."""
    if len(flowers) < LEAF_PEST_POTS:
        return
    bare = [k for k, f in enumerate(flowers) if f == "none"]
    for k in rng.sample(bare, max(1, len(bare) // 3)):
        bugs[k] = True


def _climate(rng: random.Random) -> Climate:
    """A plausible greenhouse reading (ranges around the spec's example)."""
    return Climate(
        temperature=round(rng.uniform(18.0, 28.0), 1),
        humidity=round(rng.uniform(50.0, 80.0), 1),
        co2=round(rng.uniform(400.0, 900.0)),
        light=round(rng.uniform(5000.0, 20000.0), -2),
        soil_moisture=round(rng.uniform(0.2, 0.5), 2),
    )


def moved_pots(world: World, seed: int, count: int, shift: tuple[float, float] = (0.05, 0.25),
               turn: float = 0.3) -> World:
    """``world`` after someone moved ``count`` of its pots (chosen by ``seed``): each shifted by
    ``shift[0]``..``shift[1]`` m in a random direction and turned by up to ``turn`` rad, a move
    redrawn until the world stays valid (no pot in another, none off the floor)."""
    rng = random.Random(seed)
    pots = list(world.pots)
    for k in rng.sample(range(len(pots)), min(count, len(pots))):
        for _ in range(100):
            d, a = rng.uniform(*shift), rng.uniform(-math.pi, math.pi)
            p = pots[k].model_copy(update={"x": round(pots[k].x + d * math.cos(a), 3),
                                           "y": round(pots[k].y + d * math.sin(a), 3),
                                           "facing": round(pots[k].facing + rng.uniform(-turn, turn), 4)})
            trial = world.model_copy(update={"pots": pots[:k] + [p] + pots[k + 1:]})
            if not world_problems(trial):
                pots[k] = p
                break
    return world.model_copy(update={"pots": pots, "name": f"{world.name}-moved{seed}"})
