"""The MuJoCo backend: a simulated MIRTE Master V2 in a greenhouse, behind the HAL.

``SimRobot(world, sim_config, hw_config)`` builds the greenhouse model from a world file, places the robot at
the world's spawn pose, and wires every simulated device into a ``hw.interfaces.Hal`` whose
clock advances the physics. Above the HAL nothing knows it is simulated.
"""
from __future__ import annotations

import math

import mujoco
import numpy as np

from hw.config import HwConfig
from hw.interfaces import Hal
from hw.odometry import Pose2D
from hw.wall_clock import WallPace
from sim.cameras import RendererPool, SimCamera
from sim.clock import SimClock
from sim.config import SimConfig
from sim.drive import SimDrive
from sim.engine import Engine
from sim.faults import SimFaults
from sim.greenhouse import build_greenhouse
from sim.lidar import SimLidar
from sim.sensors import SimBattery, SimEStopButton, SimImu, SimLedStrip
from sim.servos import SimServoBus
from sim.walkers import SimWalkers
from sim.world import World

BASE_JOINTS = ("base_x", "base_y", "base_yaw")
CAMERAS = {"front": "front_camera", "wrist": "wrist_camera"}


class SimRobot:
    def __init__(self, world: World, sim_config: SimConfig, hw_config: HwConfig, controllers=None):
        self.world = world
        self.sim_config, self.hw_config = sim_config, hw_config
        sc = sim_config
        self.engine = engine = Engine(build_greenhouse(world, sc.geometry), sc)
        self._base_qpos = np.array([engine.joint_qpos(j) for j in BASE_JOINTS])
        engine.data.qpos[self._base_qpos] = (world.spawn.x, world.spawn.y, world.spawn.yaw)
        engine.forward()
        self._chassis = engine.id(mujoco.mjtObj.mjOBJ_GEOM, "chassis")

        self.drive = SimDrive(engine, sc.drive, hw_config.base)
        self.battery = SimBattery(engine, sc.battery, self.drive.load, self._on_dock)
        self.servos = SimServoBus(engine, hw_config.servos, sc.servo_noise_counts, self.battery.voltage_mv)
        self.lidar = SimLidar(engine, sc.lidar)
        self.button = SimEStopButton(hw_config.estop.engaged_level)
        self.leds = SimLedStrip(engine, hw_config.leds.num_leds, sc.led_wiring)
        self.renderers = RendererPool(engine)
        cams = {k: SimCamera(self.renderers, v, sc.camera.width, sc.camera.height, sc.camera.draw_distance)
                for k, v in CAMERAS.items()}
        self.walkers = SimWalkers(engine, world.walkers, lambda: (self.truth().x, self.truth().y))
        """The people walking the greenhouse (they stop short of the robot's true position)."""
        if world.walkers:
            engine.attach(self.walkers)
        self.faults = SimFaults(engine, self.lidar, self.servos, self.battery, self.button, cams, controllers,
                                {p.id: (p.x, p.y) for p in world.pots}, self.walkers)
        self.clock = SimClock(self._paced(engine) if sc.realtime else engine.advance_to, start=engine.time)
        self.hal = Hal(
            clock=self.clock,
            wheels=self.drive,
            encoders=self.drive,
            servos=self.servos,
            lidar=self.lidar,
            imu=SimImu(engine, sc.imu_noise),
            power=self.battery,
            estop_button=self.button,
            leds=self.leds,
            cameras=cams,
        )

    @staticmethod
    def _paced(engine: Engine):
        pace = WallPace(engine.time)

        def advance(t: float) -> None:
            pace.wait(t)
            engine.advance_to(t)

        return advance

    def truth(self) -> Pose2D:
        """Ground-truth base pose in the world frame (what odometry is judged against)."""
        x, y, yaw = self.engine.data.qpos[self._base_qpos]
        return Pose2D(float(x), float(y), float(yaw))

    def _on_dock(self) -> bool:
        """The robot stands on its dock: the charger's contacts reach it (``battery.dock_reach``)."""
        dock, here = self.world.dock_pose, self.truth()
        return math.hypot(here.x - dock.x, here.y - dock.y) <= self.sim_config.battery.dock_reach

    def touching(self) -> list[str]:
        """Names of the world geoms the chassis is in contact with right now (bumps)."""
        pairs = self.engine.data.contact.geom
        hits = np.concatenate([pairs[pairs[:, 0] == self._chassis, 1], pairs[pairs[:, 1] == self._chassis, 0]])
        return sorted({mujoco.mj_id2name(self.engine.model, mujoco.mjtObj.mjOBJ_GEOM, int(g)) or f"geom {g}" for g in hits})

    def place(self, x: float, y: float, yaw: float) -> None:
        """Teleport the base (scene set-up for snapshots and tests, never the control stack)."""
        self.engine.data.qpos[self._base_qpos] = (x, y, yaw)
        self.engine.data.qvel[:] = 0.0
        self.engine.forward()

    def close(self) -> None:
        self.renderers.close()
