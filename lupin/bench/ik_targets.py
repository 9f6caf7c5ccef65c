"""Target classes for judging the camera aim (``arm.ik``), each with the answer it should get.

Reachable targets alone flatter a solver: every one has an answer. These classes also ask
for the impossible and for the edge, and the benchmark reports how each is answered.

- ``reachable``: a random in-window pose that looks down far enough, a point on its axis
  inside the range band, where a bloom can be (``arm.aim.sample_reachable_targets``). Solve.
- ``beyond_reach``: farther from the pan origin than the chain's full length plus
  ``max_range`` (``arm.aim.max_reach``, an upper bound), so unreachable by construction. Refuse.
- ``below_floor``: under the floor plane, within reach otherwise. Refuse.
- ``inside_body``: inside the robot's chassis envelope. Refuse.
- ``outside_joint_limits``: bearings between the pan window's end and the bearing whose
  half-turn would bring the other end back in (-89..-87 deg, 91..93 deg), at least 0.4 m out:
  the camera's axis lies in the vertical plane through the pan axis, and the nearest plane the
  pan window allows is at least 1 deg away, so the axis passes at least 0.4 sin(1 deg) = 7 mm
  from the target, more than the 5 mm tolerance. Unreachable because of the windows. Refuse.
- ``just_inside`` / ``just_outside``: the outer edge of the reachable set in the pan plane,
  sampled on a grid of every in-window pose (1.5 deg per joint) that looks down far enough,
  points of its axis from ``min_range`` to ``max_range``, in 1 cm height bands: just inside is
  the farthest point of a band that some grid pose reaches with 1 cm of range to spare
  (reachable by construction); just outside lies ``OUTSIDE_M`` beyond the band's edge, at the
  same height. The grid can only under-estimate the edge (measured: with the 5 mm tolerance,
  1 of 40 targets 3 cm out was still solvable, none at 4 cm), so ``OUTSIDE_M`` is 4 cm. Solve /
  refuse. A just-outside target the solver does solve, checked, counts as ``solved``: the
  edge was wrong, not the answer.

Each class is generated from its own seed, away from the floor and the body unless that is
the class's point, at bearings inside the pan window.
"""
from __future__ import annotations

import math

import numpy as np

from arm import limits
from arm.aim import bloom_can_be_at, max_reach, sample_reachable_targets
from arm.config import IkConfig, KinematicsConfig
from arm.kinematics import planar

EXPECTED = {"reachable": "solved", "beyond_reach": "refused", "below_floor": "refused", "inside_body": "refused",
            "outside_joint_limits": "refused", "just_inside": "solved", "just_outside": "refused"}
"""The answer each class should get."""
OUTSIDE_M = 0.04
"""How far beyond the sampled edge of the reachable set a ``just_outside`` target lies, m."""
GRID_DEG = 1.5
"""Joint step of the edge's grid, deg."""
RANGE_MARGIN = 0.01
"""Range kept to spare by the grid points of the edge, m."""


def _bearing_point(k: KinematicsConfig, bearing: float, radius: float, z: float) -> np.ndarray:
    ox, oy, _ = k.pan_origin
    return np.array([ox + radius * math.cos(bearing), oy + radius * math.sin(bearing), z])


def _safe_bearing(rng) -> float:
    lo, hi = limits.JOINT_LIMITS["shoulder_pan"]
    return float(rng.uniform(lo + 0.05, hi - 0.05))


def beyond_reach(n: int, seed: int, k: KinematicsConfig, c: IkConfig) -> list[np.ndarray]:
    rng, reach, out = np.random.default_rng(seed), max_reach(k, c), []
    while len(out) < n:
        d = rng.uniform(reach + 0.02, reach + 1.0)
        z = rng.uniform(0.0, 0.6)
        dz = z - k.pan_origin[2]
        if abs(dz) >= d:
            continue
        out.append(_bearing_point(k, _safe_bearing(rng), math.sqrt(d * d - dz * dz), z))
    return out


def below_floor(n: int, seed: int, k: KinematicsConfig, c: IkConfig) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [_bearing_point(k, _safe_bearing(rng), rng.uniform(0.25, 0.6), c.floor_z - rng.uniform(0.005, 0.2))
            for _ in range(n)]


def inside_body(n: int, seed: int, k: KinematicsConfig, c: IkConfig) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(c.body_min), np.asarray(c.body_max)
    return [rng.uniform(lo + 0.005, hi - 0.005) for _ in range(n)]


def outside_joint_limits(n: int, seed: int, k: KinematicsConfig, c: IkConfig) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        deg = rng.uniform(-89.0, -87.0) if i % 2 == 0 else rng.uniform(91.0, 93.0)
        out.append(_bearing_point(k, math.radians(deg), rng.uniform(0.4, 0.6), rng.uniform(0.1, 0.35)))
    return out


def reach_edge(k: KinematicsConfig, c: IkConfig, band: float = 0.01) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(band heights, edge radius per band, the farthest grid point with range to spare (r, z)
    per band), in the pan plane relative to the pan origin; the edge radius is over the full
    range band; bands with no grid point have radius -inf, bands with no point to spare NaN."""
    step = math.radians(GRID_DEG)
    axes = [np.arange(limits.LOWER[j] + 1e-3, limits.UPPER[j] - 1e-3 + step / 2, step) for j in (1, 2, 3)]
    q1, q2, q3 = (a.ravel() for a in np.meshgrid(*axes, indexing="ij"))
    r, z, dr, dz = planar(q1, q2, q3, k, np)
    down = dz <= -math.sin(c.min_look_down) - 1e-3
    r, z, dr, dz = r[down], z[down], dr[down], dz[down]
    lo_z = c.floor_z - k.pan_origin[2]
    edges = np.arange(lo_z, 0.8, band)
    best_r = np.full(edges.size, -np.inf)
    best_pt = np.zeros((edges.size, 2))
    edge_r = np.full(edges.size, -np.inf)
    spare = np.linspace(c.min_range + RANGE_MARGIN, c.max_range - RANGE_MARGIN, 12)
    full = np.linspace(c.min_range, c.max_range, 12)
    for along, is_full in [*((a, False) for a in spare), *((a, True) for a in full)]:
        pr, pz = r + along * dr, z + along * dz
        idx = np.floor((pz - lo_z) / band).astype(int)
        ok = (idx >= 0) & (idx < edges.size)
        idx, pr, pz = idx[ok], pr[ok], pz[ok]
        order = np.lexsort((pr, idx))  # by band, then radius: the last of each band is its max
        idx, pr, pz = idx[order], pr[order], pz[order]
        last = np.r_[idx[1:] != idx[:-1], True]
        idx, pr, pz = idx[last], pr[last], pz[last]
        if is_full:  # the edge itself: every range the band allows
            edge_r[idx] = np.maximum(edge_r[idx], pr)
            continue
        better = pr > best_r[idx]
        best_r[idx[better]] = pr[better]
        best_pt[idx[better]] = np.column_stack([pr[better], pz[better]])
    best_pt[~np.isfinite(best_r)] = np.nan
    return edges, np.maximum(edge_r, best_r), best_pt


def borderline(n: int, seed: int, k: KinematicsConfig, c: IkConfig) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """``n`` just-inside and ``n`` just-outside targets at the reachable set's outer edge."""
    rng = np.random.default_rng(seed)
    edges, best_r, best_pt = reach_edge(k, c)
    ox, oy, oz = k.pan_origin
    inside, outside = [], []
    usable = [i for i in range(edges.size) if np.all(np.isfinite(best_pt[i])) and best_pt[i][0] > 0.2]
    while len(inside) < n:
        i = usable[int(rng.integers(len(usable)))]
        bearing = _safe_bearing(rng)
        c_, s_ = math.cos(bearing), math.sin(bearing)
        r_in, z_in = best_pt[i]
        t_in = np.array([ox + r_in * c_, oy + r_in * s_, oz + z_in])
        r_out = best_r[i] + OUTSIDE_M
        t_out = np.array([ox + r_out * c_, oy + r_out * s_, oz + z_in])
        if not (bloom_can_be_at(t_in, c) and bloom_can_be_at(t_out, c) and t_in[2] >= c.floor_z + 0.01):
            continue
        inside.append(t_in)
        outside.append(t_out)
    return inside, outside


def target_classes(n: int, seed: int, k: KinematicsConfig, c: IkConfig, reachable: int) -> dict[str, list[np.ndarray]]:
    """Every class: ``reachable`` targets of the reachable one, ``n`` of each other."""
    inside, outside = borderline(n, seed + 5, k, c)
    return {
        "reachable": sample_reachable_targets(reachable, seed, k, c),
        "beyond_reach": beyond_reach(n, seed + 1, k, c),
        "below_floor": below_floor(n, seed + 2, k, c),
        "inside_body": inside_body(n, seed + 3, k, c),
        "outside_joint_limits": outside_joint_limits(n, seed + 4, k, c),
        "just_inside": inside,
        "just_outside": outside,
    }
