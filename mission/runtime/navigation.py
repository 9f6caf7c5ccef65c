"""Navigation on a robot: the nav stack assembled from config and put on the scheduler.

Seed rates: MPPI 20 Hz, local costmap 5 Hz, global costmap and replanning 1 Hz. The navigator
reads wheel odometry, the measured twist and the lidar through callbacks, and writes only into
the twist_mux's ``auto`` source; the base controller (10 Hz) reads the mux, so autonomy goes
through the same arbitration and e-stop as a human.
"""
from __future__ import annotations

from mission.runtime.robot import Robot
from nav.costmap.layered import global_costmap, local_costmap
from nav.localisation import Localisation, OdometryOnly
from nav.mppi.controller import MppiController
from nav.navigator import Navigator, Sources
from nav.planner import NavfnPlanner

AUTO = "auto"


def attach_navigation(robot: Robot, localisation: Localisation | None = None) -> Navigator:
    """Build the navigator on ``robot``'s services and schedule its three ticks."""
    cfg = robot.config.nav
    base = robot.base
    sources = Sources(
        odom_pose=lambda: base.odometry.pose,
        odom_twist=lambda: base.odometry.twist,
        scan=robot.hal.lidar.latest_scan,
        publish=lambda twist, now: robot.mux.publish(AUTO, twist, now),
        estop=robot.estop.engaged,
    )
    nav = Navigator(cfg, sources, localisation or OdometryOnly(), local_costmap(cfg.costmap),
                    global_costmap(cfg.costmap), NavfnPlanner(cfg.planner), MppiController(cfg.mppi, cfg.costmap))
    sched = robot.scheduler
    sched.every("nav.local_costmap", cfg.navigator.local_costmap_rate, nav.tick_local_costmap)
    sched.every("nav.planner", cfg.navigator.global_costmap_rate, nav.tick_planner)
    sched.every("nav.controller", cfg.mppi.frequency, nav.tick_control)
    return nav
