"""The robots layer: the fleet's other robots kept out of, each where it says it is (issue 34).

A robot's lidar sees little of another: its lidar puck and its arm, the chassis being below the
scan plane, so on the scan alone robots drove into each other (the fleet benches: 20 contacts
between two robots on 24 pots, 54 head-on meetings with a dead robot that the others could not
see). Every robot of a fleet says where it is through the router (``mission.link.peers``: its
own belief, its map pose composed with its dock), and this layer draws each other robot's
footprint into the costmap as the person layer draws a person (``nav.costmap.people``): lethal
out to ``robot_radius + margin + robot_radius`` from its centre (its footprint, the margin, this
robot's inscribed radius), then the inflation's falloff over ``gradient``. The planner goes round
it, MPPI keeps its distance, and where it stands in the only way the navigator waits as for a
person (the master without people, ``Costmap.without_people``, has no robots either: a robot
moves on, like a person).

No stretch along a robot's velocity, unlike a walker's: the other robot keeps out of this one
the same way. A robot that dies (its liveliness token gone) stands where it last said it was, so
the peers' source keeps that pose until the robot is heard from again; it says the robot is
``silent``, and a silent robot is drawn with ``still_margin`` and ``still_gradient``: it does not
move, so a pot it died at can still be looked at from beside it (``mission.patrol.aside``).

Peers come in the ``map`` frame; ``frame`` gives map's pose in this costmap's frame (the
identity for the global costmap, ``odom -> map`` for the local one).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from hw.odometry import Pose2D
from hw.people import Person
from nav.costmap.config import PersonLayerConfig, RobotsLayerConfig
from nav.costmap.people import PersonLayer
from nav.grid_geometry import GridGeometry


PEER_REACH = 1.0
"""A person the robot waits for who stands this near another robot's told pose is taken for that
robot in the wait's words (``nav.waits``), m: the people tracker drops tracks within 0.45 m of
one (``mission.runtime.people.ROBOT_REACH``), yet on ``fleet.handover_small`` robots still waited
"out of a walker's way" with no one in the greenhouse: each robot's pose is its own SLAM
belief composed with its dock, and two robots' beliefs part by tenths of a metre."""


@dataclass(frozen=True)
class Peer:
    """Another robot of the fleet, where it last said it was."""

    name: str
    x: float
    y: float
    """Its centre, this robot's ``map`` frame, m."""
    yaw: float
    silent: bool = False
    """Not heard from lately (``mission.link.peers.SILENT``): it stands where it last said,
    kept out of by ``still_margin`` and ``still_gradient`` instead (it will not move)."""


PeerSource = Callable[[], Sequence[Peer]]
"""What the layer reads at every rebuild: the other robots, map frame."""


def no_peers() -> Sequence[Peer]:
    """The source of a robot alone."""
    return ()


class RobotsLayer:
    def __init__(self, config: RobotsLayerConfig, robot_radius: float, cost_scaling_factor: float,
                 frame: Callable[[], Pose2D] = Pose2D):
        self.config, self.robot_radius = config, robot_radius
        self.peers: PeerSource = no_peers
        """The other robots (map frame); the link sets it when the robot joins a fleet."""
        self._discs = [PersonLayer(PersonLayerConfig(clearance=margin, gradient=gradient, predict_time=0.0, min_confidence=0.0),
                                   robot_radius, cost_scaling_factor, lambda silent=silent: self._bodies(silent), frame)
                       for silent, margin, gradient in ((False, config.margin, config.gradient),
                                                        (True, config.still_margin, config.still_gradient))]

    def _bodies(self, silent: bool) -> list[Person]:
        """Each peer (heard from lately, or ``silent``) as a standing body of the footprint's
        radius (the person layer's shape)."""
        return [Person(k, p.x, p.y, 0.0, 0.0, self.robot_radius, 1.0) for k, p in enumerate(self.peers()) if p.silent == silent]

    def near(self, x: float, y: float, reach: float = PEER_REACH) -> bool:
        """Does another robot of the fleet say it stands within ``reach`` of map point (x, y)?"""
        return any(np.hypot(p.x - x, p.y - y) <= reach for p in self.peers())

    def apply(self, master: np.ndarray, geometry: GridGeometry) -> np.ndarray:
        """``master`` with every peer's costs over it; the same array with no peers about."""
        for discs in self._discs:
            master = discs.apply(master, geometry)
        return master
