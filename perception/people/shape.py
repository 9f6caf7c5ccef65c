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
follow, which brings the pots back near 0.10: their 3x3 normal equations are solved in closed
form for all segments at once (the radius's row eliminated, a 2x2 left), because the tracker
runs at the scan rate on the robot's CPU (``perception.people`` cost: issue 28 asks 1 ms a
scan) and a batched LAPACK solve of a handful of 3x3 systems costs more than the arithmetic.
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


def per(start: np.ndarray, *columns: np.ndarray) -> np.ndarray:
    """Per-segment sums of each of ``columns`` (arrays over the returns), one row per column:
    one ``reduceat`` for them all."""
    return np.add.reduceat(np.array(columns), start, axis=1)


def fit(points: np.ndarray, segments: Segments) -> Fits:
    """Line and circle fits of each segment of ``points`` ((N, 2), the segments' returns in
    order, ``segments.count`` of them each)."""
    s = len(segments.count)
    if not s:
        empty = np.zeros(0)
        return Fits(empty, empty, empty, np.zeros((0, 2)))
    n = segments.count.astype(float)
    start = segments.start
    label = np.repeat(np.arange(s), segments.count)
    mean = np.add.reduceat(points, start, axis=0) / n[:, None]
    u, v = (points - mean[label]).T
    z = u * u + v * v
    suu, suv, svv, suz, svz, sz = per(start, u * u, u * v, v * v, u * z, v * z, z)
    a, b, c = suu / n, suv / n, svv / n
    smaller = (a + c) / 2 - np.sqrt(((a - c) / 2) ** 2 + b * b)
    line_rms = np.sqrt(np.maximum(smaller, 0.0))
    # circle: minimise sum (z + D u + E v + F)^2; centred, sum u = sum v = 0, so F = -mean z
    # and [[suu, suv], [suv, svv]] [D, E] = -[suz, svz]
    det = suu * svv - suv * suv
    solid = (det > 1e-12 * np.maximum(suu + svv, 1e-12) ** 2) & (segments.count >= 3)
    safe = np.where(solid, det, 1.0)
    d = (-suz * svv + svz * suv) / safe
    e = (-svz * suu + suz * suv) / safe
    cu, cv = -d / 2, -e / 2
    radius = np.sqrt(np.maximum(d * d / 4 + e * e / 4 + sz / n, 0.0))
    for _ in range(GEOMETRIC_STEPS):
        du, dv = u - cu[label], v - cv[label]
        dist = np.maximum(np.hypot(du, dv), 1e-9)
        ju, jv = -du / dist, -dv / dist  # d(dist - r)/d(cx, cy); d(dist - r)/dr = -1
        res = dist - radius[label]
        quu, quv, qvv, qu, qv, ru, rv, r = per(start, ju * ju, ju * jv, jv * jv, ju, jv, ju * res, jv * res, res)
        # J'J = [[quu, quv, -qu], [quv, qvv, -qv], [-qu, -qv, n]], J'res = [ru, rv, -r], with a
        # little Levenberg-Marquardt damping on the diagonal: an arc so flat it is nearly a line
        # (a wall's sliver, a box face) makes the normal equations singular (all its returns
        # pull one way). The radius is eliminated (its row), and the 2x2 left solved in closed form.
        damp = DAMPING * (quu + qvv + n + 1e-12)
        m = n + damp
        a11, a12, a22 = quu + damp - qu * qu / m, quv - qu * qv / m, qvv + damp - qv * qv / m
        b1, b2 = -ru + qu * r / m, -rv + qv * r / m
        det2 = a11 * a22 - a12 * a12
        ok = solid & (det2 != 0.0)
        det2 = np.where(ok, det2, 1.0)
        su = np.where(ok, (b1 * a22 - b2 * a12) / det2, 0.0)
        sv = np.where(ok, (a11 * b2 - a12 * b1) / det2, 0.0)
        sr = np.where(ok, (r + qu * su + qv * sv) / m, 0.0)
        cu, cv, radius = cu + su, cv + sv, radius + sr
    solid &= np.isfinite(radius) & np.isfinite(cu) & np.isfinite(cv)
    off = np.hypot(u - cu[label], v - cv[label]) - radius[label]
    circle_rms = np.sqrt(per(start, off * off)[0] / n)
    centre_uv = np.stack([cu, cv], axis=1)
    return Fits(line_rms, np.where(solid, radius, np.inf), np.where(solid, circle_rms, np.inf),
                np.where(solid[:, None], mean + centre_uv, np.nan))
