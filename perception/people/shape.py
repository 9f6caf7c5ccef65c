"""Each segment's shape: a line and a circle fitted to its returns, as leg_tracker's features do.

Size alone cannot tell a standing pair of legs from a 0.3 m box seen corner-on (two faces, each
no wider than a leg) or from a moved pot (one arc): issue 28 items 1-2. What can is shape:

- a box's face is straight: the line fits it to the lidar's noise (~1 cm), and its two faces
  meet at the corner, one continuous L with no gap between them;
- a leg is an arc of radius ~0.05-0.09 m (``sim.walkers.LEG_RADIUS`` 0.07, real legs alike),
  bulging towards the lidar (its centre lies beyond the returns);
- a pot is an arc too, of the pots' radius (``patrol.pot_radius`` 0.10), a little wider.

Both fits are linear least squares, sums over each segment's returns in one compiled loop
(numba: the numpy version's sixty-odd array calls a scan cost more than the arithmetic): the
line is the principal axis of the returns (its RMS residual the square root of the smaller
eigenvalue of their covariance), the circle the algebraic (Kasa) fit x^2 + y^2 + D x + E y + F
= 0 on coordinates centred on the segment's mean, which makes the 3x3 normal equations split
into F and a closed-form 2x2 solve. The Kasa fit
pulls the radius of a short noisy arc inwards (a 0.10 m pot came out at a leg's 0.06-0.08 in a
third of the scans), so a few Gauss-Newton steps on the returns' true distances from the circle
follow, which brings the pots back near 0.10: their 3x3 normal equations are solved in closed
form (the radius's row eliminated, a 2x2 left), because the tracker runs at the scan rate on
the robot's CPU (``perception.people`` cost: issue 28 asks 1 ms a scan).
"""
from __future__ import annotations

from dataclasses import dataclass

import math

import numpy as np
from numba import njit

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


@njit(cache=True)
def _fit(points, start, count, steps, damping):
    """The fits of each segment, one loop over its returns per sum (see ``fit``)."""
    s = len(count)
    line_rms, radius, circle_rms = np.empty(s), np.full(s, np.inf), np.full(s, np.inf)
    centre = np.full((s, 2), np.nan)
    for j in range(s):
        a0, n = start[j], count[j]
        mx = my = 0.0
        for i in range(a0, a0 + n):
            mx += points[i, 0]
            my += points[i, 1]
        mx /= n
        my /= n
        suu = suv = svv = suz = svz = sz = 0.0
        for i in range(a0, a0 + n):
            u, v = points[i, 0] - mx, points[i, 1] - my
            z = u * u + v * v
            suu += u * u
            suv += u * v
            svv += v * v
            suz += u * z
            svz += v * z
            sz += z
        a, b, c = suu / n, suv / n, svv / n
        smaller = (a + c) / 2 - math.sqrt(((a - c) / 2) ** 2 + b * b)
        line_rms[j] = math.sqrt(max(smaller, 0.0))
        # circle: minimise sum (z + D u + E v + F)^2; centred, sum u = sum v = 0, so F = -mean z
        # and [[suu, suv], [suv, svv]] [D, E] = -[suz, svz]
        det = suu * svv - suv * suv
        if not (det > 1e-12 * max(suu + svv, 1e-12) ** 2 and n >= 3):
            continue
        d = (-suz * svv + svz * suv) / det
        e = (-svz * suu + suz * suv) / det
        cu, cv = -d / 2, -e / 2
        r = math.sqrt(max(d * d / 4 + e * e / 4 + sz / n, 0.0))
        for _ in range(steps):
            quu = quv = qvv = qu = qv = ru = rv = rr = 0.0
            for i in range(a0, a0 + n):
                du, dv = points[i, 0] - mx - cu, points[i, 1] - my - cv
                dist = max(math.sqrt(du * du + dv * dv), 1e-9)
                ju, jv = -du / dist, -dv / dist  # d(dist - r)/d(cx, cy); d(dist - r)/dr = -1
                res = dist - r
                quu += ju * ju
                quv += ju * jv
                qvv += jv * jv
                qu += ju
                qv += jv
                ru += ju * res
                rv += jv * res
                rr += res
            # J'J = [[quu, quv, -qu], [quv, qvv, -qv], [-qu, -qv, n]], J'res = [ru, rv, -r], with
            # a little Levenberg-Marquardt damping on the diagonal: an arc so flat it is nearly a
            # line (a wall's sliver, a box face) makes the normal equations singular (all its
            # returns pull one way). The radius is eliminated (its row), the 2x2 left solved.
            damp = damping * (quu + qvv + n + 1e-12)
            m = n + damp
            a11, a12, a22 = quu + damp - qu * qu / m, quv - qu * qv / m, qvv + damp - qv * qv / m
            b1, b2 = -ru + qu * rr / m, -rv + qv * rr / m
            det2 = a11 * a22 - a12 * a12
            if det2 != 0.0:
                su, sv = (b1 * a22 - b2 * a12) / det2, (a11 * b2 - a12 * b1) / det2
                sr = (rr + qu * su + qv * sv) / m
                cu, cv, r = cu + su, cv + sv, r + sr
        if not (math.isfinite(r) and math.isfinite(cu) and math.isfinite(cv)):
            continue
        off2 = 0.0
        for i in range(a0, a0 + n):
            du, dv = points[i, 0] - mx - cu, points[i, 1] - my - cv
            off = math.sqrt(du * du + dv * dv) - r
            off2 += off * off
        radius[j], circle_rms[j] = r, math.sqrt(off2 / n)
        centre[j, 0], centre[j, 1] = mx + cu, my + cv
    return line_rms, radius, circle_rms, centre


def fit(points: np.ndarray, segments: Segments) -> Fits:
    """Line and circle fits of each segment of ``points`` ((N, 2), the segments' returns in
    order, ``segments.count`` of them each)."""
    if not len(segments.count):
        empty = np.zeros(0)
        return Fits(empty, empty, empty, np.zeros((0, 2)))
    return Fits(*_fit(np.ascontiguousarray(points, dtype=np.float64), segments.start.astype(np.int64),
                      segments.count.astype(np.int64), GEOMETRIC_STEPS, DAMPING))
