"""Simulated cameras: render offscreen (EGL) only when a frame is requested.

One ``mujoco.Renderer`` per image size is shared by all cameras of that size and created on
first use, so a run that never looks costs nothing. Frames come back in OpenCV's BGR order,
like ``cv2.VideoCapture`` on the robot.

The robot's cameras draw only the geoms that can show in their view (their bounding sphere
touches the camera's frustum) within ``draw_distance`` of them (sim config). MuJoCo draws every
geom in its scene, in view or not, so a 180-pot greenhouse cost five times the built-in one per
frame; it leaves a geom whose alpha is 0 out of the scene, so the others are made transparent for
the one frame and put back at once (nothing else runs in between: no physics step, no lidar ray
sees them). Frustum culling changes no pixel; the draw distance drops only what is too far to
read. The cost of a frame then follows what is in front of the robot, not the greenhouse's size.
"""
from __future__ import annotations

import math

import mujoco
import numpy as np

from hw.interfaces import DeviceError
from sim.engine import Engine


class RendererPool:
    def __init__(self, engine: Engine):
        self.engine = engine
        self._renderers: dict[tuple[int, int], mujoco.Renderer] = {}

    def render(self, camera: str | int | mujoco.MjvCamera, width: int, height: int,
               draw_distance: float | None = None) -> np.ndarray:
        """RGB uint8 HxWx3 of the current state; with ``draw_distance`` (a named camera), only
        the geoms within that many metres of the camera are drawn."""
        with self.engine.spending():
            return self._render(camera, width, height, draw_distance)

    def _render(self, camera, width: int, height: int, draw_distance: float | None) -> np.ndarray:
        key = (width, height)
        if key not in self._renderers:
            m = self.engine.model
            m.vis.global_.offwidth = max(m.vis.global_.offwidth, width)
            m.vis.global_.offheight = max(m.vis.global_.offheight, height)
            self._renderers[key] = mujoco.Renderer(m, height, width)
        r = self._renderers[key]
        # No mj_forward here: the kinematics of the last step are current to within one 5 ms
        # step, and recomputing them must never perturb the physics of a deterministic run.
        if draw_distance is None:
            r.update_scene(self.engine.data, camera=camera)
            return r.render()
        m, d = self.engine.model, self.engine.data
        hidden = np.flatnonzero(~_in_view(m, d, self.engine.id(mujoco.mjtObj.mjOBJ_CAMERA, camera),
                                          width / height, draw_distance))
        alpha = m.geom_rgba[hidden, 3].copy()
        m.geom_rgba[hidden, 3] = 0.0
        try:
            r.update_scene(d, camera=camera)
        finally:
            m.geom_rgba[hidden, 3] = alpha
        return r.render()

    def close(self) -> None:
        for r in self._renderers.values():
            r.close()
        self._renderers.clear()


def _in_view(m: mujoco.MjModel, d: mujoco.MjData, cam: int, aspect: float, far: float) -> np.ndarray:
    """Per geom: may its bounding sphere show in camera ``cam``'s view, no farther than ``far``?
    (Conservative: a sphere touching the frustum counts. A plane, the floor, has no bounding
    sphere, MuJoCo's rbound 0: always in view.)"""
    rel = (d.geom_xpos - d.cam_xpos[cam]) @ d.cam_xmat[cam].reshape(3, 3)  # camera frame: x right, y up, looking down -z
    depth, r = -rel[:, 2], m.geom_rbound
    ty = math.tan(math.radians(m.cam_fovy[cam]) / 2)
    tx = ty * aspect
    sides = ((np.abs(rel[:, 0]) - depth * tx) / math.hypot(1.0, tx) <= r) & \
            ((np.abs(rel[:, 1]) - depth * ty) / math.hypot(1.0, ty) <= r)
    return (sides & (depth >= -r) & (np.linalg.norm(rel, axis=1) - r <= far)) | (r == 0)


class SimCamera:
    """Implements the HAL's Camera for one named MuJoCo camera."""

    def __init__(self, pool: RendererPool, name: str, width: int, height: int, draw_distance: float | None = None):
        pool.engine.id(mujoco.mjtObj.mjOBJ_CAMERA, name)  # fail early on a missing camera
        self.pool = pool
        self.name = name
        self.width = width
        self.height = height
        self.draw_distance = draw_distance
        self.dropout_until = -1.0
        """Until this sim time every capture fails, as a USB camera that stops delivering does."""

    def capture(self) -> np.ndarray:
        if self.pool.engine.time < self.dropout_until:
            raise DeviceError(f"camera {self.name}: no frame (dropout)")
        return np.ascontiguousarray(self.pool.render(self.name, self.width, self.height, self.draw_distance)[:, :, ::-1])
