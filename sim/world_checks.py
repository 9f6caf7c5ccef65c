"""Cross-entry checks of a greenhouse world: geometry, unique ids and tags, climate keys.

Pydantic checks each entry on its own (sim/world.py); what involves several entries is here.
Pots are circles of ``GreenhouseGeometry.pot_radius`` (spec/world.md: ~0.10 m) and the robot a
circle of ``ROBOT_RADIUS``. The spec rejects impossible geometry: a pot in or through a wall,
overlapping pots, a pot in a box, a box outside the floor, a spawn that is outside the floor or
touches a pot or a box; ids must be unique, and so must tags (a tag identifies its pot).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from sim.config import GreenhouseGeometry

if TYPE_CHECKING:
    from sim.world import Obstacle, World

ROBOT_RADIUS = 0.22
"""Radius of the circle that encloses the robot's footprint, m. The spawn circle must not touch
a wall, a pot or an obstacle, or the robot would start inside something (spec: "a spawn inside
an obstacle" is impossible geometry)."""

_EPS = 1e-9  # geometry tolerance: exactly touching pots or boxes are allowed

def world_problems(
    world: World,
    geometry: GreenhouseGeometry | None = None,
    robot_radius: float = ROBOT_RADIUS,
) -> list[str]:
    """Every problem that involves more than one entry, one line each (without the file name).

    Pots are circles of ``geometry.pot_radius`` (spec/world.md: ~0.10 m; sim/config.py
    :class:`GreenhouseGeometry` is where the sim fixes it); the robot is a circle of
    ``robot_radius``. The spec calls for rejecting impossible geometry: a pot in or through a
    wall, overlapping pots, a pot in a box, a box outside the floor, a spawn that is outside the
    floor or touches a pot or a box. It also asks for unique ids; tags must be unique too (a tag
    identifies its pot) and climate may only be keyed by a tag that some pot carries.
    """
    r = (geometry or GreenhouseGeometry()).pot_radius
    fx, fy = world.floor.x, world.floor.y
    out: list[str] = []

    first_id: dict[str, int] = {}
    first_tag: dict[int, int] = {}
    for i, pot in enumerate(world.pots):
        where = _pot(i, world)
        if pot.id in first_id:
            out.append(f"{where}: field 'id': duplicate of pots[{first_id[pot.id]}]")
        first_id.setdefault(pot.id, i)
        if pot.tag is not None:
            if pot.tag in first_tag:
                out.append(
                    f"{where}: field 'tag': tag {pot.tag} is already on {_pot(first_tag[pot.tag], world)}"
                )
            first_tag.setdefault(pot.tag, i)
        out += [f"{where}: {p}" for p in _circle_in_floor(pot.x, pot.y, r, fx, fy, "pot")]

    out += _overlapping_pots(world, r)

    for j, box in enumerate(world.obstacles):
        corners = _box_corners(box)
        bad = [c for c in corners if not (-_EPS <= c[0] <= fx + _EPS and -_EPS <= c[1] <= fy + _EPS)]
        if bad:
            cx, cy = bad[0]
            out.append(
                f"obstacles[{j}]: fields 'x', 'y', 'sx', 'sy', 'yaw': the box reaches outside the "
                f"floor: corner ({cx:.2f}, {cy:.2f}) is not in [0, {fx:.2f}] x [0, {fy:.2f}]"
            )
        for i, pot in enumerate(world.pots):
            d = _distance_to_box(pot.x, pot.y, box)
            if d < r - _EPS:
                out.append(
                    f"{_pot(i, world)} overlaps obstacles[{j}]: {_gap(d, r, 'pot')} (fields 'x', 'y')"
                )

    s = world.spawn
    out += [f"spawn{p}" for p in robot_circle_problems(world, s.x, s.y, r, robot_radius)]
    out += _spawns_problems(world, r, robot_radius)
    if world.dock is not None:
        d = world.dock
        out += [f"dock{p}" for p in robot_circle_problems(world, d.x, d.y, r, robot_radius)]

    for tag in world.climate:
        if tag not in first_tag:
            out.append(f"climate[{tag}]: key {tag}: no pot carries tag {tag}")
    out += _walker_problems(world, r)
    return out


def _spawns_problems(world: World, pot_radius: float, robot_radius: float) -> list[str]:
    """A fleet's docks (spec/world.md ``spawns``): the first is ``spawn``; each clear like the
    spawn; no two robots' circles touching (each starts on its own dock)."""
    spawns, out = world.spawns, []
    if not spawns:
        return out
    first, s = spawns[0], world.spawn
    if (first.x, first.y, first.yaw) != (s.x, s.y, s.yaw):
        out.append(f"spawns[0]: fields 'x', 'y', 'yaw': ({first.x}, {first.y}, {first.yaw}) is not the spawn pose "
                   f"({s.x}, {s.y}, {s.yaw}); the first of the fleet's docks is `spawn`")
    for i, p in enumerate(spawns[1:], 1):
        out += [f"spawns[{i}]{q}" for q in robot_circle_problems(world, p.x, p.y, pot_radius, robot_radius)]
    for i, p in enumerate(spawns):
        for j, q in enumerate(spawns[:i]):
            gap = math.hypot(p.x - q.x, p.y - q.y)
            if gap < 2 * robot_radius - _EPS:
                out.append(f"spawns[{i}]: fields 'x', 'y': {gap:.2f} m from spawns[{j}]; two robots need "
                           f"{2 * robot_radius:.2f} m between their centres")
    return out


WALKING_SPEED = (0.2, 1.5)
"""Speeds a walking path accepts, m/s (spec/world.md: people walk at 0.8 to 1.4; 0.2 is a
shuffle, 1.5 a hurry)."""
CROUCHING_MAX_WIDTH = 0.6
"""Widest a crouching walker may be, m: a cart is pushed standing (``width`` above this is one)."""


def _walker_problems(world: World, pot_radius: float) -> list[str]:
    """A walker's path must keep its body (a circle of half its width) on the floor and clear of
    every pot and box (a worker who stays put: the one point); ids unique; a walking path has a
    walking speed; a crouching worker pushes no cart."""
    out, seen = [], {}
    for k, w in enumerate(world.walkers):
        where = f"walkers[{k}] (id {w.id})"
        if w.id in seen:
            out.append(f"{where}: field 'id': duplicate of walkers[{seen[w.id]}]")
        seen.setdefault(w.id, k)
        low, high = WALKING_SPEED
        if len(w.path) > 1 and (w.speed is None or not low <= w.speed <= high):
            got = "missing" if w.speed is None else f"got {w.speed:g}"
            out.append(f"{where}: field 'speed': a path of {len(w.path)} points is walked at {low:g}..{high:g} m/s "
                       f"({got})")
        if w.posture == "crouching" and w.width > CROUCHING_MAX_WIDTH:
            out.append(f"{where}: field 'width': a crouching worker is at most {CROUCHING_MAX_WIDTH:g} m wide "
                       f"(a cart is pushed standing; got {w.width:g})")
        half = w.width / 2 if w.posture == "standing" else CROUCHING_MAX_WIDTH / 2
        for a, b in zip(w.path, w.path[1:] or w.path):
            crossed = _path_crossing(world, a, b, half, pot_radius)
            if crossed:
                what = "the point" if len(w.path) == 1 else "the segment"
                span = f"({a[0]:g}, {a[1]:g})" + ("" if len(w.path) == 1 else f" -> ({b[0]:g}, {b[1]:g})")
                out.append(f"{where}: field 'path': {what} {span} {'touches' if len(w.path) == 1 else 'crosses'} {crossed}")
                break
    return out


def _path_crossing(world: World, a, b, half: float, pot_radius: float) -> str | None:
    """What a body of radius ``half`` walking from a to b would walk into, or None."""
    n = max(2, int(math.hypot(b[0] - a[0], b[1] - a[1]) / 0.02) + 1)
    for t in (k / (n - 1) for k in range(n)):
        x, y = a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])
        wall = _circle_in_floor(x, y, half, world.floor.x, world.floor.y, "walker")
        if wall:
            return f"a wall ({wall[0].split(': ', 1)[-1]})" if ": " in wall[0] else "a wall"
        for i, pot in enumerate(world.pots):
            if math.hypot(pot.x - x, pot.y - y) < pot_radius + half - _EPS:
                return f"{_pot(i, world)} at ({pot.x:g}, {pot.y:g})"
        for j, box in enumerate(world.obstacles):
            if _distance_to_box(x, y, box) < half - _EPS:
                return f"obstacles[{j}] at ({box.x:g}, {box.y:g})"
    return None


def robot_circle_problems(world: World, x: float, y: float, pot_radius: float,
                          robot_radius: float = ROBOT_RADIUS) -> list[str]:
    """Why the robot's circle at (x, y) is outside the floor or touches a pot or a box (each
    line starts with ': ' or ' overlaps ...', ready to follow the name of what was placed)."""
    out = [f": {p}" for p in _circle_in_floor(x, y, robot_radius, world.floor.x, world.floor.y, "robot")]
    for i, pot in enumerate(world.pots):
        d, need = math.hypot(pot.x - x, pot.y - y), robot_radius + pot_radius
        if d < need - _EPS:
            got, want = _pair(d, need)
            out.append(
                f" overlaps {_pot(i, world)}: centres {got} m apart, need >= {want} m "
                f"(robot radius {robot_radius:.2f} m + pot radius {pot_radius:.2f} m) (fields 'x', 'y')"
            )
    for j, box in enumerate(world.obstacles):
        d = _distance_to_box(x, y, box)
        if d < robot_radius - _EPS:
            out.append(f" overlaps obstacles[{j}]: {_gap(d, robot_radius, 'robot')} (fields 'x', 'y')")
    return out


def _overlapping_pots(world: World, r: float) -> list[str]:
    """Pairs of pots closer than two radii; a sweep along x keeps big generated worlds fast."""
    order = sorted(range(len(world.pots)), key=lambda i: world.pots[i].x)
    found: list[tuple[int, int, float]] = []
    for a, i in enumerate(order):
        pi = world.pots[i]
        for j in order[a + 1:]:
            pj = world.pots[j]
            if pj.x - pi.x >= 2 * r:
                break
            d = math.hypot(pj.x - pi.x, pj.y - pi.y)
            if d < 2 * r - _EPS:
                found.append((max(i, j), min(i, j), d))
    out = []
    for later, earlier, d in sorted(found):
        got, want = _pair(d, 2 * r)
        out.append(
            f"{_pot(later, world)} overlaps {_pot(earlier, world)}: centres {got} m apart, "
            f"need >= {want} m (fields 'x', 'y')"
        )
    return out


def _circle_in_floor(x: float, y: float, r: float, fx: float, fy: float, what: str) -> list[str]:
    """Why a circle is not fully inside [0, fx] x [0, fy] (empty list: it is)."""
    out = []
    for field, v, size, low_wall, high_wall in (("x", x, fx, "west", "east"), ("y", y, fy, "south", "north")):
        if size < 2 * r:
            out.append(f"field '{field}': the floor is {size:.2f} m across, too small for a {what} "
                       f"of radius {r:.2f} m")
        elif v < r - _EPS or v > size - r + _EPS:
            wall = low_wall if v < r else high_wall
            out.append(
                f"field '{field}': the {what} (radius {r:.2f} m) crosses the {wall} wall: "
                f"need {r:.2f} <= {field} <= {size - r:.2f} m (got {v:g})"
            )
    return out


def _box_corners(box: Obstacle) -> list[tuple[float, float]]:
    c, s = math.cos(box.yaw), math.sin(box.yaw)
    hx, hy = box.sx / 2, box.sy / 2
    return [(box.x + c * u - s * v, box.y + s * u + c * v) for u in (-hx, hx) for v in (-hy, hy)]


def _distance_to_box(x: float, y: float, box: Obstacle) -> float:
    """Distance from a point to a yawed box's footprint (0 inside it)."""
    c, s = math.cos(box.yaw), math.sin(box.yaw)
    dx, dy = x - box.x, y - box.y
    u, v = c * dx + s * dy, -s * dx + c * dy  # the point in the box frame
    return math.hypot(max(abs(u) - box.sx / 2, 0.0), max(abs(v) - box.sy / 2, 0.0))


def _gap(d: float, need: float, what: str) -> str:
    if d <= 0:
        return f"the {what} centre is inside the box"
    got, want = _pair(d, need)
    return f"the {what} centre is {got} m from the box, need >= {want} m (its radius)"


def _pair(got: float, need: float) -> tuple[str, str]:
    """Format two distances with enough decimals that they visibly differ."""
    for digits in (2, 3, 4, 6):
        a, b = f"{got:.{digits}f}", f"{need:.{digits}f}"
        if a != b:
            return a, b
    return f"{got!r}", f"{need!r}"


def _pot(i: int, world: World) -> str:
    return f"pots[{i}] (id {world.pots[i].id})"
