"""The physics engine: owns MjModel/MjData and advances them to a requested time.

Time moves in whole physics steps (integer step count, so runs never drift), in chunks of
``physics.drive_update``. Before each chunk the attached devices get a ``pre_chunk(t)`` call:
the wheels re-target the body's traction servos from their forward kinematics, the servos
move their setpoints along the Hiwonder move(position, time) ramp. Everything else (lidar,
cameras, IMU) is read lazily when a consumer asks, so nothing is computed that nobody uses.

``cpu_s`` counts the process CPU seconds the simulator itself spends (physics here, the
cameras' renders and the lidar's rays through ``spending()``), so a benchmark can tell the
robot runtime's own cost from the simulator's (``lupin bench runtime.cpu``). It is process
time, so the renderer's worker threads count too; it never steers anything.
"""
from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Iterator, Protocol

import mujoco

from sim.config import SimConfig


class ChunkDevice(Protocol):
    def pre_chunk(self, t: float) -> None: ...


class Engine:
    def __init__(self, model: mujoco.MjModel, config: SimConfig):
        self.model = model
        self.data = mujoco.MjData(model)
        self.config = config
        self.model.opt.timestep = config.physics.timestep
        self._dt = config.physics.timestep
        self._steps = 0
        self._chunk = max(1, round(config.physics.drive_update / self._dt))
        self._devices: list[ChunkDevice] = []
        self.cpu_s = 0.0
        """Process CPU seconds spent simulating (physics, renders, lidar rays)."""

    # --- names -----------------------------------------------------------------------------
    def id(self, kind: mujoco.mjtObj, name: str) -> int:
        i = mujoco.mj_name2id(self.model, kind, name)
        if i < 0:
            raise KeyError(f"sim model has no {kind.name[6:].lower()} named {name!r}")
        return i

    def joint_qpos(self, name: str) -> int:
        return int(self.model.jnt_qposadr[self.id(mujoco.mjtObj.mjOBJ_JOINT, name)])

    def joint_dof(self, name: str) -> int:
        return int(self.model.jnt_dofadr[self.id(mujoco.mjtObj.mjOBJ_JOINT, name)])

    def actuator(self, name: str) -> int:
        return self.id(mujoco.mjtObj.mjOBJ_ACTUATOR, name)

    # --- time ------------------------------------------------------------------------------
    @property
    def time(self) -> float:
        return self._steps * self._dt

    def attach(self, device: ChunkDevice) -> None:
        self._devices.append(device)

    def forward(self) -> None:
        mujoco.mj_forward(self.model, self.data)

    @contextmanager
    def spending(self) -> Iterator[None]:
        """Count the CPU of the block as the simulator's."""
        t0 = time.process_time()
        try:
            yield
        finally:
            self.cpu_s += time.process_time() - t0

    def advance_to(self, t: float) -> None:
        """Step physics until the sim time reaches ``t`` (rounded to a whole step)."""
        target = round(t / self._dt)
        if self._steps >= target:
            return
        with self.spending():
            while self._steps < target:
                n = min(self._chunk - self._steps % self._chunk, target - self._steps)
                if self._steps % self._chunk == 0:
                    now = self.time
                    for device in self._devices:
                        device.pre_chunk(now)
                mujoco.mj_step(self.model, self.data, nstep=n)
                self._steps += n

    def warnings(self) -> dict[str, int]:
        """MuJoCo warnings raised so far (name -> count); empty for a healthy run."""
        out = {}
        for name, w in mujoco.mjtWarning.__members__.items():
            if name != "mjNWARNING" and self.data.warning[int(w)].number:
                out[name] = int(self.data.warning[int(w)].number)
        return out
