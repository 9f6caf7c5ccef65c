"""Motion models: sampled controls -> feasible velocities -> trajectories (reference steps 3-4).

``predict`` walks each sampled control sequence through the envelope: column 0 is the robot's
current velocity; for t >= 1, ``v[t] = clamp(cv[t-1])`` to the velocity limits and to
``v[t-1] +- dt * accel``. ``integrate`` then rolls the poses out the way Nav2 does: the yaw
accumulates ``wz * dt`` and each step's translation uses the *previous* step's yaw.

Both loops are sequential in time (each step depends on the last), which numpy cannot vectorise
without a Python loop of 56 steps x 3 axes; a fused numba kernel does predict + integrate in
one pass over the batch (``lupin bench nav.mppi`` gives the side-by-side).

``OmniModel`` samples (vx, vy, wz), so every batch holds sideways candidates (seed: "the
lateral capability is not penalised away"); ``DiffDriveModel`` pins vy to zero, the seed's
"structurally absent" case, used to show what the strafe buys.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from nav.mppi.config import MppiConfig


@numba.njit(cache=True, fastmath=True, parallel=False)
def _rollout(cvx, cvy, cwz, v0, lo, hi, acc, dt, x0, y0, yaw0, vx, vy, wz, x, y, yaw):
    b, t_steps = cvx.shape
    for k in range(b):
        pvx, pvy, pwz = v0[0], v0[1], v0[2]
        px, py, pyaw = x0, y0, yaw0
        for t in range(t_steps):
            if t > 0:
                nvx = min(max(cvx[k, t - 1], lo[0]), hi[0])
                nvy = min(max(cvy[k, t - 1], lo[1]), hi[1])
                nwz = min(max(cwz[k, t - 1], lo[2]), hi[2])
                pvx = min(max(nvx, pvx - acc[0] * dt), pvx + acc[0] * dt)
                pvy = min(max(nvy, pvy - acc[1] * dt), pvy + acc[1] * dt)
                pwz = min(max(nwz, pwz - acc[2] * dt), pwz + acc[2] * dt)
            vx[k, t] = pvx
            vy[k, t] = pvy
            wz[k, t] = pwz
            c, s = math.cos(pyaw), math.sin(pyaw)
            px += (pvx * c - pvy * s) * dt
            py += (pvx * s + pvy * c) * dt
            pyaw += pwz * dt
            x[k, t] = px
            y[k, t] = py
            yaw[k, t] = pyaw


class OmniModel:
    """Holonomic: (vx, vy, wz) all sampled."""

    holonomic = True

    def __init__(self, config: MppiConfig):
        c = config
        self.lo = np.array([c.vx_min, c.vy_min, -c.wz_max], dtype=np.float32)
        self.hi = np.array([c.vx_max, c.vy_max, c.wz_max], dtype=np.float32)
        self.acc = np.array([c.ax_max, c.ay_max, c.az_max], dtype=np.float32)
        self.dt = np.float32(c.model_dt)

    def rollout(self, cv: np.ndarray, v0: np.ndarray, pose: tuple[float, float, float],
                out_v: np.ndarray, out_traj: np.ndarray) -> None:
        """cv (3, B, T) sampled controls -> out_v (3, B, T) velocities, out_traj (3, B, T) x, y, yaw."""
        _rollout(cv[0], cv[1], cv[2], v0.astype(np.float32), self.lo, self.hi, self.acc, self.dt,
                 np.float32(pose[0]), np.float32(pose[1]), np.float32(pose[2]),
                 out_v[0], out_v[1], out_v[2], out_traj[0], out_traj[1], out_traj[2])


class DiffDriveModel(OmniModel):
    """vy pinned to zero: every trajectory is a forward or backward arc."""

    holonomic = False

    def __init__(self, config: MppiConfig):
        super().__init__(config)
        self.lo[1] = self.hi[1] = 0.0


def motion_model(config: MppiConfig) -> OmniModel:
    return {"omni": OmniModel, "diff": DiffDriveModel}[config.motion_model](config)
