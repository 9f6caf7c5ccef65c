"""Shape evidence (perception/people/shape.py, legs.py): a standing pair of legs is two leg arcs
with a gap between them; a box seen corner-on and a pot are not, on synthetic C1 scans."""
from __future__ import annotations

import math

import numpy as np

from perception.people import PeopleConfig
from perception.people.explained import StaticScene
from perception.people.legs import arcs, find, pairs
from perception.people.segments import Segments, split, unwrap
from perception.people import shape
from perception.people.shape import fit
from tests.perception.people.synthetic import POT_RADIUS, Scene, greenhouse, mapped

CONFIG = PeopleConfig()
ROBOT = (1.0, 2.0, 0.0)
WALLS = mapped(greenhouse())


def segments_of(points: np.ndarray) -> Segments:
    return split(points, np.hypot(*(points - ROBOT[:2]).T), CONFIG.jump, CONFIG.jump_per_metre)


def near_segments(scan: np.ndarray, x: float, y: float) -> tuple[np.ndarray, Segments]:
    """The returns of a whole revolution within 0.3 m of (x, y), in unwrapped order, and their
    segments."""
    scan = scan[unwrap(scan)]
    pts = scan[np.hypot(scan[:, 0] - x, scan[:, 1] - y) < 0.3]
    return pts, segments_of(pts)


def test_line_and_circle_fits_recover_a_line_and_a_circle():
    t = np.linspace(0, 1, 20)
    line = np.stack([t, 0.5 * t + 1], axis=1)
    a = np.linspace(-1.2, 1.2, 15)
    circle = np.stack([2 + 0.07 * np.cos(a), 3 + 0.07 * np.sin(a)], axis=1)
    pts = np.concatenate([line, circle])
    f = fit(pts, Segments(np.array([0, 20]), np.array([20, 15]), np.zeros((2, 2)), np.zeros((2, 2)), np.zeros((2, 2))))
    assert f.line_rms[0] < 1e-6 and np.isinf(f.radius[0])  # collinear: no circle
    assert abs(f.radius[1] - 0.07) < 1e-9 and f.circle_rms[1] < 1e-9
    assert np.allclose(f.circle_centre[1], [2, 3])
    assert f.line_rms[1] > 0.005


def detections(scene: Scene, robot=ROBOT, pots=(), scans: int = 10):
    """The pairs of legs found in each of ``scans`` noisy scans."""
    static = StaticScene(WALLS, np.array(pots).reshape(-1, 2), POT_RADIUS, CONFIG.margin)
    out = []
    for k in range(scans):
        pts = scene.scan(robot, seed=k)
        out.append(find(pts, np.array(robot[:2]), static.explained(pts), CONFIG).pairs)
    return out


def test_two_leg_arcs_with_a_gap_are_a_pair_of_legs():
    for distance in (0.8, 1.5, 2.0):
        found = detections(greenhouse().legs(ROBOT[0] + distance, 2.0, heading=math.pi))
        assert sum(len(f) == 1 for f in found) >= 5, distance  # the rest: one leg arc's fit off
        assert all(np.hypot(f[:, 0] - ROBOT[0] - distance, f[:, 1] - 2.0).max() < 0.1 for f in found if len(f))


def test_a_box_corner_on_is_not_a_pair_of_legs():
    for distance in (0.8, 1.5, 2.0):
        for yaw in (math.pi / 4, 0.3, 1.0):
            assert not any(len(f) for f in detections(greenhouse().box(ROBOT[0] + distance, 2.0, 0.3, 0.3, yaw))), \
                (distance, yaw)


def test_a_box_face_split_in_two_by_the_scan_start_is_one_again():
    """The revolution starts straight ahead: without ``unwrap`` a box dead ahead is cut in two
    at the array's ends (its two faces, corner-on), each as narrow as a leg."""
    s = greenhouse().box(2.0, 2.0, 0.3, 0.3, math.pi / 4)
    pts = s.scan(ROBOT)
    near = np.hypot(pts[:, 0] - 2.0, pts[:, 1] - 2.0) < 0.4
    assert len(segments_of(pts[near]).count) == 2
    assert len(segments_of(pts[unwrap(pts)][near[unwrap(pts)]]).count) == 1


def test_a_pot_arc_is_not_a_leg():
    """Over 20 noisy scans each, up to 1.5 m (where the distance rules act): a pot's arc is
    rarely taken for a leg's (a fifth at most, the noise on 9-20 returns; at 2 m, 7 returns,
    nearer a third), a leg's at the same distance mostly is (one arc alone is never a person:
    that takes a pair)."""
    for distance in (0.8, 1.2, 1.5):
        rate = {}
        for radius in (POT_RADIUS, 0.07):
            thing = Scene(walls=greenhouse().walls, circles=[(ROBOT[0] + distance, 2.0, radius)])
            hits = 0
            for seed in range(20):
                pts, segs = near_segments(thing.scan(ROBOT, seed=seed), ROBOT[0] + distance, 2.0)
                assert len(segs.count) == 1
                hits += bool(arcs(segs, fit(pts, segs), np.array(ROBOT[:2]), CONFIG)[0])
            rate[radius] = hits / 20
        assert rate[POT_RADIUS] <= 0.2 and rate[0.07] >= 0.6, (distance, rate)


def test_two_pots_side_by_side_or_a_moved_pot_are_not_a_pair_of_legs():
    side_by_side = Scene(walls=greenhouse().walls, circles=[(2.5, 1.85, POT_RADIUS), (2.5, 2.15, POT_RADIUS)])
    assert not any(len(f) for f in detections(side_by_side))
    for dx, dy in ((0.15, -0.05), (0.15, 0.05), (-0.15, 0.05), (0.0, 0.16)):
        moved = Scene(walls=greenhouse().walls, circles=[(2.5 + dx, 2.0 + dy, POT_RADIUS)])
        assert not any(len(f) for f in detections(moved, pots=[(2.5, 2.0)])), (dx, dy)


def test_a_two_leg_gap_check_tells_a_corner_from_legs():
    """Two arcs meeting end to end (no gap) are not a pair even with their centres apart."""
    a = np.linspace(-1.0, 1.0, 8)
    left = np.stack([2 - 0.06 * np.cos(a), 1.9 + 0.06 * np.sin(a)], axis=1)
    right = np.stack([2 - 0.06 * np.cos(a), 2.1 + 0.06 * np.sin(a)], axis=1)
    for second, gap in ((right, True), (right - [0, 0.08], False)):
        pts = np.concatenate([left, second])
        segs = Segments(np.array([0, 8]), np.array([8, 8]), np.array([pts[:8].mean(0), pts[8:].mean(0)]),
                        np.array([pts[:8].min(0), pts[8:].min(0)]), np.array([pts[:8].max(0), pts[8:].max(0)]))
        f = fit(pts, segs)
        leg = arcs(segs, f, np.array(ROBOT[:2]), CONFIG)
        assert leg.all()
        assert pairs(pts, segs, f, leg, CONFIG)[0, 1] == gap


def test_a_nearly_straight_sliver_fits_without_breaking_the_scan_loop():
    """A wall's sliver of three returns on an arc of a kilometre's radius made the Gauss-Newton
    equations singular (a LinAlgError that killed the runtime's people task mid-scenario)."""
    for radius in (1e2, 1e4, 1e6):
        a = np.linspace(0.0, 0.1 / radius, 3)
        pts = np.stack([radius * np.cos(a) - radius, radius * np.sin(a)], axis=1)
        f = fit(pts, Segments(np.array([0]), np.array([3]), np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2))))
        assert not arcs(Segments(np.array([0]), np.array([3]), pts.mean(axis=0, keepdims=True), pts.min(axis=0, keepdims=True),
                                 pts.max(axis=0, keepdims=True)), f, np.array([0.0, -1.0]), CONFIG).any()
        assert np.isinf(f.radius[0]) or f.radius[0] > 1.0


def arc_segments(seed: int, count: int, radius=(0.03, 0.3), span=(0.3, 2.5),
                 noise: float = 0.01) -> tuple[np.ndarray, Segments]:
    """``count`` arcs of random radius and span (within ``radius``, ``span``) and size, with
    ``noise`` (m, standard deviation) on their returns, one segment each, in one array."""
    rng = np.random.default_rng(seed)
    parts = []
    for _ in range(count):
        a0, wide, r = rng.uniform(-math.pi, math.pi), rng.uniform(*span), rng.uniform(*radius)
        a = np.linspace(a0, a0 + wide, int(rng.integers(3, 25)))
        centre = rng.uniform(-3, 3, 2)
        parts.append(centre + np.stack([np.cos(a), np.sin(a)], axis=1) * r + rng.normal(0, noise, (len(a), 2)))
    count_each = np.array([len(p) for p in parts])
    start = np.cumsum(count_each) - count_each
    zero = np.zeros((count, 2))
    return np.concatenate(parts), Segments(start, count_each, zero, zero, zero)


def test_segments_are_fitted_each_on_its_own_whatever_else_is_fitted_with_it():
    """The shape pass fits only the segments that could be leg arcs: a segment's fit must not
    depend on which others share the batch."""
    for seed in range(20):
        pts, segs = arc_segments(seed, 6)
        together = fit(pts, segs)
        for k in range(6):
            one = Segments(np.array([0]), segs.count[k:k + 1], segs.centre[k:k + 1], segs.lo[k:k + 1], segs.hi[k:k + 1])
            alone = fit(pts[segs.start[k]:segs.start[k] + segs.count[k]], one)
            for name in ("line_rms", "radius", "circle_rms", "circle_centre"):
                assert np.allclose(getattr(alone, name)[0], getattr(together, name)[k], rtol=1e-9, atol=1e-12), (seed, k)


def test_each_fit_step_is_the_gauss_newton_step_on_the_distances_to_the_circle(monkeypatch):
    """One step from the algebraic circle (no steps) is the Gauss-Newton step of the returns'
    distances from the circle, here solved as the full damped 3x3 normal equations (the fit
    eliminates the radius and solves the rest in closed form)."""
    for seed in range(20):
        pts, segs = arc_segments(seed, 1)
        monkeypatch.setattr(shape, "GEOMETRIC_STEPS", 0)
        (cx, cy), r = fit(pts, segs).circle_centre[0], fit(pts, segs).radius[0]
        monkeypatch.setattr(shape, "GEOMETRIC_STEPS", 1)
        stepped = fit(pts, segs)
        d = np.hypot(pts[:, 0] - cx, pts[:, 1] - cy)
        jac = -np.stack([(pts[:, 0] - cx) / d, (pts[:, 1] - cy) / d, np.ones_like(d)], axis=1)
        jtj = jac.T @ jac
        step = np.linalg.solve(jtj + shape.DAMPING * np.trace(jtj) * np.eye(3), -jac.T @ (d - r))
        assert np.allclose(stepped.circle_centre[0], [cx + step[0], cy + step[1]], rtol=0, atol=1e-9), seed
        assert abs(stepped.radius[0] - (r + step[2])) < 1e-9, seed


def test_a_leg_sized_arc_is_fitted_to_the_least_squares_circle():
    """The three Gauss-Newton steps (the radius eliminated, the rest solved in closed form) end
    at the geometric fit of a leg seen well (a leg's radius, a third of its round or more in
    view, a few millimetres of noise): moving the centre or the radius a millimetre either way
    only adds to the returns' squared distances from the circle. (Noisier and shorter arcs
    settle over more steps; their fit stays what the leg window was chosen on.)"""
    for seed in range(40):
        pts, segs = arc_segments(seed, 1, radius=CONFIG.leg_radius, span=(2.0, 3.0), noise=0.003)
        f = fit(pts, segs)
        cx, cy = f.circle_centre[0]

        def cost(dx=0.0, dy=0.0, dr=0.0):
            return np.sum((np.hypot(pts[:, 0] - cx - dx, pts[:, 1] - cy - dy) - f.radius[0] - dr) ** 2)

        best = cost()
        assert abs(math.sqrt(best / len(pts)) - f.circle_rms[0]) < 1e-12
        for step in ((1e-3, 0, 0), (-1e-3, 0, 0), (0, 1e-3, 0), (0, -1e-3, 0), (0, 0, 1e-3), (0, 0, -1e-3)):
            assert cost(*step) >= best - 1e-12, (seed, step)
