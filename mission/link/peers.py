"""The fleet's robots to each other: where each one is, so that each keeps out of the others.

The lidar sees little of another robot (its puck and its arm; the chassis is below the scan
plane), so robots tell each other where they are (issue 34). Each robot on a router puts its own
pose on ``lupin/<robot>/where`` ten times a second, in the fleet's frame (the first dock's,
spec/fleet.md): its own belief, its map pose (``map -> odom`` and odometry) composed with its
dock in that frame (``fleet.docks``; the sim world's ``spawns`` in ``lupin fleet sim``). Nothing
there is ground truth. Each robot reads every other's (``lupin/*/where``: the router lets a
robot read these and publish only its own, ``fleet.router``) and hands them, in its own map
frame, to both costmaps' robots layer (``nav.costmap.robots``), which keep their footprints out
of the plan and of MPPI's rollouts.

Nothing is forgotten: a robot whose liveliness token went (its computer died, or it was switched
off) still stands where it last said it was, an obstacle, until it is heard from again; a robot
carried away is an obstacle where it stood until it speaks (a false obstacle costs a detour, a
forgotten one a collision). Not heard from for ``SILENT`` s, it is ``silent``: a robot that
stands still there, kept out of by less (``nav.costmap.robots``). Silence is the link's, so it is
timed on the wall clock the runtime is given (``Service.wall_now``), not the robot's: a fleet sim
running faster than real time can outrun the router, which is why it waits for the poses
(``hear``: each message carries its sender's clock).
Messages arrive on Zenoh's thread; the runtime reads a copy.
"""
from __future__ import annotations

import json
import logging
import math
import threading
from typing import Callable

import zenoh

from hw.odometry import Pose2D
from mission.link.outbox import Outbox
from mission.link.wire import dumps
from nav.costmap.robots import Peer, no_peers
from nav.frames import compose, inverse

log = logging.getLogger("lupin.link")

WHERE = "lupin/*/where"
RATE = 10.0
"""Poses put a second, Hz: the lidar's rate; a robot at 0.3 m/s moves 3 cm between two."""
SILENT = 2.0
"""Wall seconds without a pose from a robot before it counts as silent: twenty of its poses
missed; a robot that lives puts one every 0.1 s of its clock (more often still in a sim faster
than real time)."""
TASK = "link.peers"


def where_key(robot: str) -> str:
    """Where robot ``robot`` says it is (fleet frame)."""
    return f"lupin/{robot}/where"


def read_where(payload: bytes) -> tuple[Pose2D, float] | None:
    """The pose in a ``where`` message and its stamp (the sender's clock, s); None for anything
    else (ignored, never an obstacle's end)."""
    try:
        msg = json.loads(payload)
        x, y, yaw = (float(v) for v in msg["pose"])
        t = float(msg.get("t", math.nan))
    except (ValueError, KeyError, TypeError, AttributeError):
        return None
    return (Pose2D(x, y, yaw), t) if all(map(math.isfinite, (x, y, yaw))) else None


class Peers:
    def __init__(self, session: zenoh.Session, outbox: Outbox, robot: str, dock: Pose2D,
                 clock: Callable[[], float]):
        """``dock``: this robot's dock (its map frame's origin) in the fleet's frame; ``clock``:
        the wall clock silence is timed on (the service's ``wall_now``)."""
        self.outbox, self.robot, self.dock, self.clock = outbox, robot, dock, clock
        self._from_fleet = inverse(dock)
        self._lock = threading.Lock()
        self._told = threading.Condition(self._lock)
        """Notified with every pose heard (``hear`` waits on it)."""
        self._last: dict[str, Pose2D] = {}
        """Each other robot's last pose, fleet frame."""
        self._heard: dict[str, float] = {}
        """When (``clock``) each other robot was last heard from."""
        self._stamp: dict[str, float] = {}
        """The stamp (the sender's clock) of each other robot's last pose."""
        self._sub = session.declare_subscriber(WHERE, self._on_sample)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        robot = str(sample.key_expr).split("/")[1]
        heard = read_where(sample.payload.to_bytes())
        if robot != self.robot and heard is not None:
            with self._told:
                self._last[robot], self._stamp[robot] = heard
                self._heard[robot] = self.clock()
                self._told.notify_all()

    def tell(self, map_pose: Pose2D, now: float) -> None:
        """Put this robot's pose (map frame, its own belief) on its key, in the fleet's frame."""
        p = compose(self.dock, map_pose)
        msg = {"t": round(now, 3), "pose": [round(p.x, 3), round(p.y, 3), round(p.yaw, 3)]}
        self.outbox.post(where_key(self.robot), lambda: dumps(msg))

    def around(self) -> list[Peer]:
        """The other robots as last heard, this robot's map frame, by name."""
        with self._lock:
            last = sorted(self._last.items())
            now = self.clock()
            silent = {name for name, _ in last if now - self._heard[name] > SILENT}
        out = []
        for name, pose in last:
            q = compose(self._from_fleet, pose)
            out.append(Peer(name, q.x, q.y, q.yaw, name in silent))
        return out

    def behind(self, now: float, lag: float) -> bool:
        """Is a robot that is not silent last heard from at a stamp before ``now - lag`` (the
        shared clock of a fleet sim, ``mission.jobs.fleet_sim``)?"""
        with self._lock:
            return self._behind(now, lag)

    def hear(self, now: float, lag: float, timeout: float) -> bool:
        """Wait until no robot is ``behind``, woken by each pose heard, ``timeout`` s at most;
        whether none is."""
        with self._told:
            return self._told.wait_for(lambda: not self._behind(now, lag), timeout)

    def _behind(self, now: float, lag: float) -> bool:
        wall = self.clock()
        return any(self._stamp[r] < now - lag for r in self._last if wall - self._heard[r] <= SILENT)

    def attach(self, nav, scheduler) -> None:
        """Tell ``nav``'s pose at ``RATE`` on ``scheduler`` and keep the others out of both of
        its costmaps."""
        scheduler.every(TASK, RATE, lambda now: self.tell(nav.map_pose(), now))
        for costmap in (nav.local_costmap, nav.global_costmap):
            costmap.robots.peers = self.around

    def close(self, nav, scheduler) -> None:
        """Off the fleet: nothing told, nothing kept out of (the robot is alone again)."""
        scheduler.cancel(TASK)
        for costmap in (nav.local_costmap, nav.global_costmap):
            costmap.robots.peers = no_peers
        self._sub.undeclare()
