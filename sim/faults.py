"""Run-time fault injection for the simulated robot (spec/events.md names the actions).

Each method is one fault an events file or a scenario can script: the sim must be
able to misbehave the way the seed says the robot does.
"""
from __future__ import annotations

import math

import mujoco
import numpy as np

from sim.cameras import SimCamera
from sim.engine import Engine
from sim.greenhouse import PARKED_Z, SPARE_BOXES
from sim.lidar import SimLidar
from sim.sensors import SimBattery, SimEStopButton
from sim.servos import SimServoBus


class SimFaults:
    def __init__(self, engine: Engine, lidar: SimLidar, servos: SimServoBus, battery: SimBattery,
                 button: SimEStopButton, cameras: dict[str, SimCamera], controllers=None,
                 pots: dict[str, tuple[float, float]] | None = None, walkers=None):
        self.engine = engine
        self.pots = {} if pots is None else pots
        """Each pot's centre (world frame), where it stands now: the scene's, which every robot's
        faults share (``sim.scene``)."""
        self._lidar = lidar
        self._servos = servos
        self._battery = battery
        self._button = button
        self._cameras = cameras
        self.controllers = controllers
        self._walkers = walkers

    def estop(self, engaged: bool) -> None:
        """Press or release the physical button."""
        self._button.pressed = bool(engaged)

    def lidar_dropout(self, duration: float) -> None:
        """No scans for ``duration`` seconds (a USB hiccup)."""
        self._lidar.dropout_until = self.engine.time + duration

    def lidar_blind(self, duration: float) -> None:
        """Scans arrive on time for ``duration`` seconds with every return invalid (the lidar
        covered or sun-blinded)."""
        self._lidar.blind_until = self.engine.time + duration

    def camera_dropout(self, camera: str, duration: float) -> None:
        """No frames from ``camera`` for ``duration`` seconds: every capture fails."""
        self._cameras[camera].dropout_until = self.engine.time + duration

    def servo_stall(self, joint: str, mode: str = "unload") -> None:
        """The seed's shoulder_lift trip: ``unload`` (goes limp) or ``latch`` (ignores commands)."""
        if mode == "unload":
            self._servos.unload(joint)
        elif mode == "latch":
            self._servos.latch(joint)
        else:
            raise ValueError(f"servo_stall mode must be 'unload' or 'latch', got {mode!r}")

    def battery(self, voltage: float | None) -> None:
        """Force the pack voltage (None gives control back to the battery model)."""
        self._battery.forced_voltage = voltage

    def battery_drain(self, load: float, duration: float) -> None:
        """An extra load on the pack for ``duration`` s (a stuck wheel, a short): ``load`` amps
        more than the robot's work draws, which the power monitor sees."""
        self._battery.extra_load = (float(load), self.engine.time + duration)

    def place_box(self, x: float, y: float, sx: float, sy: float, yaw: float = 0.0, h: float = 0.5) -> None:
        """Drop a box on the floor (world frame, full sizes), from the model's spare boxes."""
        m, d = self.engine.model, self.engine.data
        bodies = [self.engine.id(mujoco.mjtObj.mjOBJ_BODY, f"spare_box_{k}") for k in range(SPARE_BOXES)]
        parked = [k for k, b in enumerate(bodies) if d.mocap_pos[m.body_mocapid[b], 2] == PARKED_Z]
        if not parked:  # a box placed by any robot's faults is taken: they share the world's spares
            raise ValueError(f"at most {SPARE_BOXES} boxes can be placed in one run")
        body = bodies[parked[0]]
        geom = self.engine.id(mujoco.mjtObj.mjOBJ_GEOM, f"spare_box_{parked[0]}_geom")
        m.geom_size[geom] = (sx / 2, sy / 2, h / 2)
        m.geom_rbound[geom] = math.sqrt((sx / 2) ** 2 + (sy / 2) ** 2 + (h / 2) ** 2)
        m.geom_aabb[geom] = (0.0, 0.0, 0.0, sx / 2, sy / 2, h / 2)  # the broad phase reads this
        mocap = m.body_mocapid[body]
        d.mocap_pos[mocap] = (x, y, h / 2)
        d.mocap_quat[mocap] = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))

    def move_pot(self, pot: str, dx: float, dy: float, dyaw: float) -> None:
        """Someone moves a pot: its centre shifted by (dx, dy) and the whole pot (its plate too)
        turned by ``dyaw`` about it, world frame. Its geoms are the world body's (static), whose
        poses MuJoCo takes from the model on every step."""
        if pot not in self.pots:
            raise ValueError(f"the world has no pot {pot!r}")
        m = self.engine.model
        names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, i) or "" for i in range(m.ngeom)]
        ids = [i for i, n in enumerate(names) if n.startswith((f"pot_{pot}_", f"tag_{pot}_")) or n == f"tag_{pot}"]
        cx, cy = self.pots[pot]
        c, s = math.cos(dyaw), math.sin(dyaw)
        turn = np.array([math.cos(dyaw / 2), 0.0, 0.0, math.sin(dyaw / 2)])
        for i in ids:
            x, y = m.geom_pos[i, 0] - cx, m.geom_pos[i, 1] - cy
            m.geom_pos[i, :2] = (cx + dx + c * x - s * y, cy + dy + s * x + c * y)
            quat = np.empty(4)
            mujoco.mju_mulQuat(quat, turn, m.geom_quat[i])
            m.geom_quat[i] = quat
        self.pots[pot] = (cx + dx, cy + dy)
        mujoco.mj_kinematics(m, self.engine.data)  # in place now, for the next render or ray

    def walker(self, walker: str, moving: bool) -> None:
        """A walker stops where it is (``moving`` False: someone stops to talk) or walks on."""
        if self._walkers is None:
            raise ValueError("this sim has no walkers")
        self._walkers.hold(walker, not moving)

    def controller_race(self, controllers: list[str], state: str) -> None:
        """Bring controllers up broken (the seed's boot race): missing, unconfigured or inactive."""
        if self.controllers is None:
            raise RuntimeError("no controller manager attached to the sim")
        for name in controllers:
            self.controllers.force(name, state)
