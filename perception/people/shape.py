"""Each segment's shape: a line and a circle fitted to its returns, as leg_tracker's features do.

Size alone cannot tell a standing pair of legs from a 0.3 m box seen corner-on (two faces, each
no wider than a leg) or from a moved pot (one arc): issue 28 items 1-2. What can is shape:

- a box's face is straight: the line fits it to the lidar's noise (~1 cm), and its two faces
  meet at the corner, one continuous L with no gap between them;
- a leg is an arc of radius ~0.05-0.09 m (``sim.walkers.LEG_RADIUS`` 0.07, real legs alike),
  bulging towards the lidar (its centre lies beyond the returns);
- a pot is an arc too, of the pots' radius (``patrol.pot_radius`` 0.10), a little wider.

Both fits are linear least squares over every segment at once (sums per segment with
``np.add.reduceat``, no per-segment Python): the line is the principal axis of the returns (its
RMS residual the square root of the smaller eigenvalue of their covariance), the circle the
algebraic (Kasa) fit x^2 + y^2 + D x + E y + F = 0 on coordinates centred on the segment's mean,
which makes the 3x3 normal equations split into F and a closed-form 2x2 solve. The Kasa fit
pulls the radius of a short noisy arc inwards (a 0.10 m pot came out at a leg's 0.06-0.08 in a
third of the scans), so a few Gauss-Newton steps on the returns' true distances from the circle
follow (batched 3x3 solves), which brings the pots back near 0.10.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from perception.people.segments import Segments


GEOMETRIC_STEPS = 3
"""Gauss-Newton steps after the algebraic fit: it starts close, and three steps settle it."""
DAMPING = 1e-6
"""Levenberg-Marquardt damping of each step, relative to the normal matrix's trace: negligible
for a true arc, enough to keep a nearly straight one's equations solvable."""


@dataclass(frozen=True)
class Fits:
    """Line and circle fits, as arrays over the segments."""

    line_rms: np.ndarray
    """(S,) RMS distance of the returns from their best line, m."""
    radius: np.ndarray
    """(S,) radius of the best circle, m (inf where the returns are collinear)."""
    circle_rms: np.ndarray
    """(S,) RMS distance of the returns from that circle, m (inf where there is none)."""
    circle_centre: np.ndarray
    """(S, 2) the circle's centre (nan where there is none)."""


def fit(points: np.ndarray, segments: Segments) -> Fits:
    """Line and circle fits of each segment of ``points`` ((N, 2), the segments' returns in
    order, ``segments.count`` of them each)."""
    s = len(segments.count)
    if not s:
        empty = np.zeros(0)
        return Fits(empty, empty, empty, np.zeros((0, 2)))
    n = segments.count.astype(float)
    label = np.repeat(np.arange(s), segments.count)
    mean = np.add.reduceat(points, segments.start, axis=0) / n[:, None]
    u, v = (points - mean[label]).T
    z = u * u + v * v

    def per(x: np.ndarray) -> np.ndarray:
        return np.add.reduceat(x, segments.start)

    suu, suv, svv = per(u * u), per(u * v), per(v * v)
    a, b, c = suu / n, suv / n, svv / n
    smaller = (a + c) / 2 - np.sqrt(((a - c) / 2) ** 2 + b * b)
    line_rms = np.sqrt(np.maximum(smaller, 0.0))
    # circle: minimise sum (z + D u + E v + F)^2; centred, sum u = sum v = 0, so F = -mean z
    # and [[suu, suv], [suv, svv]] [D, E] = -[suz, svz]
    suz, svz = per(u * z), per(v * z)
    det = suu * svv - suv * suv
    solid = (det > 1e-12 * np.maximum(suu + svv, 1e-12) ** 2) & (segments.count >= 3)
    safe = np.where(solid, det, 1.0)
    d = (-suz * svv + svz * suv) / safe
    e = (-svz * suu + suz * suv) / safe
    f = -per(z) / n
    centre_uv = np.stack([-d / 2, -e / 2], axis=1)
    radius = np.sqrt(np.maximum(d * d / 4 + e * e / 4 - f, 0.0))
    eye = np.eye(3)
    for _ in range(GEOMETRIC_STEPS):
        du, dv = u - centre_uv[label, 0], v - centre_uv[label, 1]
        dist = np.maximum(np.hypot(du, dv), 1e-9)
        jac = -np.stack([du / dist, dv / dist, np.ones_like(dist)], axis=1)  # d(dist - r)/d(cx, cy, r)
        res = dist - radius[label]
        jtj = np.zeros((s, 3, 3))
        np.add.at(jtj, label, jac[:, :, None] * jac[:, None, :])
        jtr = np.zeros((s, 3))
        np.add.at(jtr, label, jac * res[:, None])
        # a little Levenberg-Marquardt damping: an arc so flat it is nearly a line (a wall's
        # sliver, a box face) makes the normal equations singular (all its returns pull one way)
        damp = DAMPING * (np.trace(jtj, axis1=1, axis2=2) + 1e-12)[:, None, None] * eye
        step = np.linalg.solve(np.where(solid[:, None, None], jtj + damp, eye),
                               -np.where(solid[:, None], jtr, 0.0)[:, :, None])[:, :, 0]
        centre_uv = centre_uv + step[:, :2]
        radius = radius + step[:, 2]
    solid &= np.isfinite(radius) & np.isfinite(centre_uv).all(axis=1)
    off = np.hypot(u - centre_uv[label, 0], v - centre_uv[label, 1]) - radius[label]
    circle_rms = np.sqrt(per(off * off) / n)
    return Fits(line_rms, np.where(solid, radius, np.inf), np.where(solid, circle_rms, np.inf),
                np.where(solid[:, None], mean + centre_uv, np.nan))
