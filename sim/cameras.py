"""Simulated cameras: render offscreen (EGL) only when a frame is requested.

One ``mujoco.Renderer`` per image size is shared by all cameras of that size and created on
first use, so a run that never looks costs nothing. Frames come back in OpenCV's BGR order,
like ``cv2.VideoCapture`` on the robot.

The robot's cameras draw only the geoms within ``draw_distance`` of them (sim config): MuJoCo
leaves a geom whose alpha is 0 out of the scene, so the far ones are made transparent for the
one frame and put back at once (nothing else runs in between: no physics, no lidar ray sees it).
The cost of a frame then follows what is near the robot, not the size of the greenhouse.
"""
from __future__ import annotations

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
        eye = d.cam_xpos[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_CAMERA, camera)]
        far = np.flatnonzero(np.linalg.norm(d.geom_xpos - eye, axis=1) - m.geom_rbound > draw_distance)
        alpha = m.geom_rgba[far, 3].copy()
        m.geom_rgba[far, 3] = 0.0
        try:
            r.update_scene(d, camera=camera)
        finally:
            m.geom_rgba[far, 3] = alpha
        return r.render()

    def close(self) -> None:
        for r in self._renderers.values():
            r.close()
        self._renderers.clear()


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
