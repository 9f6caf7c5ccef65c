"""Navigation on a robot: localisation, the readiness cascade and the nav stack, scheduled.

Seed rates: MPPI 20 Hz, local costmap 5 Hz, global costmap and replanning 1 Hz, localisation
(SLAM's map -> odom, or AMCL) and the readiness cascade at 10 Hz, the lidar's rate. The
navigator reads wheel odometry, the measured twist and the lidar through callbacks, and writes
only into the twist_mux's ``auto`` source; the base controller (10 Hz) reads the mux, so
autonomy goes through the same arbitration and e-stop as a human. The map SLAM hands back
(once a second) becomes the global costmap's static layer.
"""
from __future__ import annotations

from hw.errors import InputError
from hw.people import Person
from mission.runtime.people import attach_people
from mission.runtime.robot import Robot
from mission.runtime.scheduler import Scheduler
from nav.amcl.localisation import AmclLocalisation
from nav.costmap.layered import global_costmap, local_costmap
from nav.localisation import Localisation, get_localisation
from nav.mppi.controller import MppiController
from nav.navigator import Navigator, Sources
from nav.occupancy import OccupancyMap
from nav.planner import NavfnPlanner
from nav.readiness import Readiness
from nav.slam.people_mask import Pressing
from nav.slam.supervisor import SlamSupervisor
from nav.walks import Walks

AUTO = "auto"
READINESS_RATE = 10.0
"""The cascade is checked at the lidar's rate: a stage fires within a scan of its event."""


class MapResetError(InputError):
    """clear_map asked of a robot that is not mapping."""


def attach_navigation(robot: Robot, localisation: Localisation | None = None) -> Navigator:
    """Build the navigator on ``robot``'s services and schedule its ticks. ``localisation``
    defaults to what config selects (``nav.slam``: SLAM, or AMCL on ``nav.map_file``)."""
    cfg = robot.config.nav
    base = robot.base
    scan = robot.hal.lidar.latest_scan
    odom_pose = lambda: base.odometry.pose  # noqa: E731
    people = attach_people(robot, lambda: localisation.map_to_odom(), lambda: getattr(localisation, "occupancy", None))
    radius, now = cfg.costmap.robot_radius, robot.scheduler.clock.now

    def gap(p: Person) -> float:
        """Body to body from the robot to ``p``, m (both odom)."""
        o = odom_pose()
        return p.gap(o.x, o.y, radius)

    walks = Walks(people.confident, now, gap)  # the navigation's people, their walks remembered
    sources = Sources(
        odom_pose=odom_pose,
        odom_twist=lambda: base.odometry.twist,
        scan=scan,
        publish=lambda twist, now: robot.mux.publish(AUTO, twist, now),
        estop=robot.estop.engaged,
        held=lambda: robot.monitor.verdict.holding or people.guard.verdict.holding,
        escape=people.guard.escape,
        people=walks,
    )
    gcm = global_costmap(cfg.costmap, walks, lambda: localisation.map_to_odom())

    def static_map(m: OccupancyMap) -> None:
        gcm.set_static(m.occupancy, m.resolution, m.origin_x, m.origin_y)

    localisation = localisation or get_localisation(cfg, odom_pose, scan, static_map, robot.hal.clock.deterministic,
                                                    Pressing(people.confident, gap, now))
    readiness = Readiness({"scans": lambda: scan() is not None, "map": localisation.has_map,
                           "transform": localisation.ready}, cfg.navigator.readiness_timeout)
    nav = Navigator(cfg, sources, localisation, local_costmap(cfg.costmap, walks, lambda: localisation.map_to_odom()), gcm, NavfnPlanner(cfg.planner),
                    MppiController(cfg.mppi, cfg.costmap), readiness)
    sched = robot.scheduler
    sched.every("nav.localisation", localisation.rate, localisation.tick)
    sched.every("nav.readiness", READINESS_RATE, readiness.tick)
    sched.every("nav.local_costmap", cfg.navigator.local_costmap_rate, nav.tick_local_costmap)
    sched.every("nav.planner", cfg.navigator.global_costmap_rate, nav.tick_planner)
    sched.every("nav.controller", cfg.mppi.frequency, nav.tick_control)
    robot.closers.append(localisation.close)
    return nav


def clear_map(nav: Navigator, now: float) -> int:
    """The map reset (seed: /lupin/nav/clear_map): clear both costmaps, so stale lethal cells do
    not linger inflated under the robot while SLAM is down, then kill the SLAM worker (respawned
    1.0 s later with an empty graph). Returns how many workers were killed."""
    if not isinstance(nav.localisation, SlamSupervisor):
        raise MapResetError("clear_map: the robot is localising on a saved map (nav.slam false); "
                            "there is no live map to reset")
    nav.local_costmap.clear()
    nav.global_costmap.clear(static=True)
    return nav.localisation.reset(now)


def final_map(nav: Navigator, scheduler: Scheduler) -> OccupancyMap | None:
    """The map the patrol ran on: SLAM's as it stands now (asked for, then the scheduler run
    until it is back: sent on the next localisation tick, answered on the one after), or the
    saved map AMCL localised on; None with neither."""
    slam = nav.localisation
    if isinstance(slam, AmclLocalisation):
        return slam.occupancy
    if not isinstance(slam, SlamSupervisor):
        return None
    slam.request_map()
    scheduler.run_for(2.0 / slam.rate)
    return slam.occupancy
