"""Camera aiming: joint angles that point the wrist camera's optical axis at a bloom, from above.

A preset stays the default pose: from the ideal approach pose it frames the pot's plant.
This is for the other cases (a bloom off-centre or at another height, or a robot that stopped
short of its ideal pose): given the bloom's position in base_link, find the pose nearest
the reference preset (``inspect`` unless told) whose optical axis passes through it, inside the joint windows, looking down at
least ``min_look_down`` and from between ``min_range`` and ``max_range`` away.

The pan angle is closed form: the camera and its axis live in the vertical plane through the
pan axis (``arm.kinematics``), so the plane must contain the target. What remains is a small
nonlinear program in (lift, elbow, wrist), built once with casadi and solved with Ipopt:

    minimise   |q - q_inspect|^2
    subject to dr * (Z - z) - dz * (R - r) = 0          the target lies on the optical axis
               min_range <= dr * (R - r) + dz * (Z - z) <= max_range
               dz <= -sin(min_look_down)                  looking down, from above
               q inside the windows of ``arm.limits``

A target nothing satisfies is *reported* (``AimResult.ok`` False with the reason), never
clipped into a pose that looks somewhere else. Three kinds are refused before the solver runs,
each with its own reason: a target below the floor or inside the robot's body (no bloom can be
there, although a camera could look at the spot), and one farther from the shoulder than the
arm and camera could be plus ``max_range`` (a bound: nothing beyond it is reachable).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from arm import limits
from arm.config import IkConfig, KinematicsConfig
from arm.kinematics import camera_ray, miss_distance, planar
from arm.presets import PRESETS

#: Starting guesses after the reference: the other reaching presets, for targets far from it.
_STARTS = ("inspect", "pick", "place", "zero")


@dataclass(frozen=True)
class AimResult:
    ok: bool
    q: np.ndarray | None
    """Joint angles in joint order (None when unreachable)."""
    miss: float = math.inf
    """Distance from the target to the optical axis, m."""
    range: float = math.nan
    """Distance from the camera to the target along the axis, m."""
    reason: str = ""


class CameraAim:
    """Solve once-built aiming problems; ``aim(target)`` for a target in base_link, metres."""

    def __init__(self, kinematics: KinematicsConfig, config: IkConfig, reference: str = "inspect"):
        self.k = kinematics
        self.config = config
        self.reference = np.array(PRESETS[reference], dtype=float)
        """The preset the answer stays nearest to (the patrol's: its ``inspect_pose``)."""
        self._starts = (reference, *(p for p in _STARTS if p != reference))
        x = ca.SX.sym("q", 3)
        p = ca.SX.sym("p", 2 + 3)  # target R, Z in the pan plane, then the reference pose
        r, z, dr, dz = planar(x[0], x[1], x[2], kinematics, ca)
        R, Z = p[0], p[1]
        g = ca.vertcat(dr * (Z - z) - dz * (R - r), dr * (R - r) + dz * (Z - z), dz)
        f = ca.sumsqr(x - p[2:])
        opts = {"ipopt.print_level": 0, "ipopt.sb": "yes", "print_time": 0,
                "ipopt.max_iter": config.max_iter, "ipopt.tol": 1e-10}
        self._solver = ca.nlpsol("camera_aim", "ipopt", {"x": x, "p": p, "f": f, "g": g}, opts)
        self._lbg = [0.0, config.min_range, -1.0]
        self._ubg = [0.0, config.max_range, -math.sin(config.min_look_down)]
        self.max_reach = max_reach(kinematics, config)

    def refusal(self, t: np.ndarray) -> str:
        """Why no pose can be asked to look at ``t`` whatever the solver finds ('' if none)."""
        c = self.config
        if t[2] < c.floor_z:
            return f"target z {t[2]:.3f} m is below the floor (z {c.floor_z:g} m in base_link)"
        if np.all(t >= c.body_min) and np.all(t <= c.body_max):
            return f"target ({t[0]:.3f}, {t[1]:.3f}, {t[2]:.3f}) m is inside the robot's body"
        d = float(np.linalg.norm(t - np.asarray(self.k.pan_origin)))
        if d > self.max_reach:
            return (f"target is {d:.2f} m from the shoulder, beyond reach (the camera sees at most "
                    f"{self.max_reach:.2f} m from it)")
        return ""

    def aim(self, target) -> AimResult:
        t = np.asarray(target, dtype=float)
        if t.shape != (3,) or not np.all(np.isfinite(t)):
            return AimResult(False, None, reason=f"target must be three finite numbers, got {target!r}")
        why = self.refusal(t)
        if why:
            return AimResult(False, None, reason=why)
        ox, oy, oz = self.k.pan_origin
        dx, dy = t[0] - ox, t[1] - oy
        R = math.hypot(dx, dy)
        bearing = math.atan2(dy, dx) if R > 1e-6 else 0.0
        lo, hi = limits.JOINT_LIMITS["shoulder_pan"]
        # The plane through the pan axis holds the target at +R (arm facing it) or, turned
        # half a turn, at -R (the arm leaning back over the pan axis towards it).
        planes = [(pan, sign * R) for pan, sign in ((bearing, 1.0), (bearing - math.pi, -1.0), (bearing + math.pi, -1.0))
                  if lo <= pan <= hi]
        if not planes:
            return AimResult(False, None, reason=f"target bearing {math.degrees(bearing):.0f} deg is outside the "
                                                 f"shoulder_pan window [{math.degrees(lo):.0f}, {math.degrees(hi):.0f}]")
        best: AimResult | None = None
        reference_start = self._starts[0]
        for pan, r in planes:
            for start in self._starts:
                result = self._solve(pan, r, t, start)
                if result.ok and (best is None or not best.ok or self._cost(result.q) < self._cost(best.q) - 1e-9):
                    best = result
                elif best is None:
                    best = result
                if best.ok and start == reference_start:
                    break  # the basin nearest the reference pose: good enough
        return best

    def _cost(self, q: np.ndarray) -> float:
        return float(np.sum((q - self.reference) ** 2))

    def _solve(self, pan: float, r: float, target: np.ndarray, start: str) -> AimResult:
        x0 = np.array(PRESETS[start][1:], dtype=float) * (1.0 if r >= 0 else -1.0)  # mirrored when leaning back
        sol = self._solver(x0=x0, p=[r, target[2] - self.k.pan_origin[2], *self.reference[1:]],
                           lbx=limits.LOWER[1:], ubx=limits.UPPER[1:], lbg=self._lbg, ubg=self._ubg)
        q = np.concatenate([[pan], np.asarray(sol["x"]).ravel()])
        return self._check(limits.clamp_arm(q), target)  # Ipopt may sit 1e-8 past a bound

    def _check(self, q: np.ndarray, target: np.ndarray) -> AimResult:
        """Accept a solver answer only if it really does what was asked (solvers can stop on
        infeasible points): in the windows, on target, in range, looking down."""
        c = self.config
        miss, along = miss_distance(q, target, self.k)
        _, _, _, dz = planar(q[1], q[2], q[3], self.k, math)
        problems = []
        if not limits.within(q, tol=1e-6):
            problems.append("outside the joint windows")
        if miss > c.tolerance:
            problems.append(f"optical axis misses it by {miss * 100:.1f} cm")
        if not (c.min_range - 1e-4 <= along <= c.max_range + 1e-4):
            problems.append(f"{along:.2f} m away (wanted {c.min_range:g}..{c.max_range:g} m)")
        if dz > -math.sin(c.min_look_down) + 1e-6:
            problems.append("not seen from above")
        if problems:
            return AimResult(False, None, miss, along, "unreachable: best pose " + ", ".join(problems))
        return AimResult(True, q, miss, along)


def max_reach(k: KinematicsConfig, config: IkConfig) -> float:
    """An upper bound of how far from the pan origin a target can be seen: the camera is at
    most the chain's length away from it (every link straight), plus ``max_range``."""
    return k.lift_height + k.upper_arm + k.forearm + math.hypot(*k.camera_offset) + config.max_range


def bloom_can_be_at(t, config: IkConfig) -> bool:
    """Above the floor and outside the robot's body: a place a bloom can be."""
    t = np.asarray(t, dtype=float)
    return bool(t[2] >= config.floor_z and not (np.all(t >= config.body_min) and np.all(t <= config.body_max)))


def sample_reachable_targets(n: int, seed: int, kinematics: KinematicsConfig, config: IkConfig,
                             margin: float = 0.02) -> list[np.ndarray]:
    """Targets spread over the reachable set (for tests and the benchmark): a random pose in
    the windows that looks down far enough, and a point on its optical axis at a random range
    inside the allowed band (``margin`` inside every bound), where a bloom can be (``margin``
    above the floor, outside the body)."""
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    while len(out) < n:
        q = rng.uniform(limits.LOWER, limits.UPPER)
        _, _, _, dz = planar(q[1], q[2], q[3], kinematics, math)
        if dz > -math.sin(config.min_look_down) - margin:
            continue
        p, d = camera_ray(q, kinematics)
        t = p + rng.uniform(config.min_range + margin, config.max_range - margin) * d
        if t[2] < config.floor_z + margin or not bloom_can_be_at(t, config):
            continue
        out.append(t)
    return out


def view_target(q, k: KinematicsConfig, height: float) -> np.ndarray | None:
    """Where the optical axis at joint angles ``q`` meets the horizontal plane ``height`` m
    above base_link (None when it does not look down at it): the spot a preset frames, which
    the patrol re-aims at when the robot stopped off its ideal pose."""
    p, d = camera_ray(q, k)
    if d[2] >= -1e-6 or p[2] <= height:
        return None
    return p + d * ((height - p[2]) / d[2])
