"""The MuJoCo backend: a simulated MIRTE Master V2 in a greenhouse, behind the HAL.

``SimRobot(world, sim_config, hw_config)`` builds the greenhouse model from a world file, places the robot at
the world's spawn pose, and wires every simulated device into a ``hw.interfaces.Hal`` whose
clock advances the physics. Above the HAL nothing knows it is simulated. With ``scene=`` and
``name=`` it is one robot of a fleet's greenhouse (``sim.scene``): its devices on its own
prefixed parts, at its own spawn and dock, its clock advancing the shared engine.
"""
from __future__ import annotations

import math

import mujoco
import numpy as np

from hw.config import HwConfig
from hw.interfaces import Hal
from hw.odometry import Pose2D
from sim.cameras import SimCamera
from sim.clock import SimClock
from sim.config import SimConfig
from sim.drive import SimDrive
from sim.faults import SimFaults
from sim.lidar import SimLidar
from sim.scene import SimScene, prefix
from sim.scope import Scope, robot_seed
from sim.sensors import SimBattery, SimEStopButton, SimImu, SimLedStrip
from sim.servos import SimServoBus
from sim.world import World

BASE_JOINTS = ("base_x", "base_y", "base_yaw")
CAMERAS = {"front": "front_camera", "wrist": "wrist_camera"}


class SimRobot:
    def __init__(self, world: World, sim_config: SimConfig, hw_config: HwConfig, controllers=None, *,
                 scene: SimScene | None = None, name: str = ""):
        """``scene`` None: a greenhouse of its own with this one robot in it (the robot file's
        names). In a fleet's ``scene``, the robot ``name`` (one of ``scene.names``): at its own
        spawn, its dock there, its devices on its prefixed names (``sim.scope``)."""
        self.world = world
        self.sim_config, self.hw_config = sim_config, hw_config
        self.owns_scene = scene is None
        self.scene = scene = scene or SimScene(world, sim_config)
        self.name = name
        sc = sim_config
        self.engine = engine = scene.engine
        index = scene.names.index(name)
        own = Scope(engine, prefix(name), robot_seed(sc.seed, index)) if name else engine
        self.spawn = world.spawn_poses[index] if name else world.spawn
        self.dock = self.spawn if name and world.spawns else world.dock_pose
        """Where this robot charges: its spawn in a fleet (spec/world.md ``spawns``: docks)."""
        self._base_qpos = np.array([own.joint_qpos(j) for j in BASE_JOINTS])
        engine.data.qpos[self._base_qpos] = (self.spawn.x, self.spawn.y, self.spawn.yaw)
        engine.forward()
        self.chassis = own.id(mujoco.mjtObj.mjOBJ_GEOM, "chassis")

        self.drive = SimDrive(own, sc.drive, hw_config.base)
        self.battery = SimBattery(own, sc.battery, self.drive.load, self._on_dock)
        self.servos = SimServoBus(own, hw_config.servos, sc.servo_noise_counts, self.battery.voltage_mv)
        self.lidar = SimLidar(own, sc.lidar)
        self.button = SimEStopButton(hw_config.estop.engaged_level)
        self.leds = SimLedStrip(own, hw_config.leds.num_leds, sc.led_wiring)
        self.renderers = scene.renderers
        cams = {k: SimCamera(self.renderers, prefix(name) + v, sc.camera.width, sc.camera.height, sc.camera.draw_distance)
                for k, v in CAMERAS.items()}
        self.walkers = scene.walkers
        """The people walking the greenhouse (they stop short of the nearest robot's true position)."""
        self.faults = SimFaults(engine, self.lidar, self.servos, self.battery, self.button, cams, controllers,
                                scene.pots, self.walkers)
        self.clock = SimClock(scene.advance, start=engine.time)
        self.hal = Hal(
            clock=self.clock,
            wheels=self.drive,
            encoders=self.drive,
            servos=self.servos,
            lidar=self.lidar,
            imu=SimImu(own, sc.imu_noise),
            power=self.battery,
            estop_button=self.button,
            leds=self.leds,
            cameras=cams,
        )
        scene.robots[name] = self

    def truth(self) -> Pose2D:
        """Ground-truth base pose in the world frame (what odometry is judged against)."""
        x, y, yaw = self.engine.data.qpos[self._base_qpos]
        return Pose2D(float(x), float(y), float(yaw))

    def _on_dock(self) -> bool:
        """The robot stands on its dock: the charger's contacts reach it (``battery.dock_reach``)."""
        dock, here = self.dock, self.truth()
        return math.hypot(here.x - dock.x, here.y - dock.y) <= self.sim_config.battery.dock_reach

    def touching(self) -> list[str]:
        """Names of the world geoms the chassis is in contact with right now (bumps)."""
        pairs = self.engine.data.contact.geom
        hits = np.concatenate([pairs[pairs[:, 0] == self.chassis, 1], pairs[pairs[:, 1] == self.chassis, 0]])
        return sorted({self.scene.geom_name(int(g)) for g in hits})

    def place(self, x: float, y: float, yaw: float) -> None:
        """Teleport the base (scene set-up for snapshots and tests, never the control stack)."""
        self.engine.data.qpos[self._base_qpos] = (x, y, yaw)
        self.engine.data.qvel[:] = 0.0
        self.engine.forward()

    def close(self) -> None:
        if self.owns_scene:
            self.scene.close()
