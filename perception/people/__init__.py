"""perception.people: who stands or walks near the robot, from the lidar scan (issue 28 item 1).

A module per idea:

- :mod:`perception.people.returns`: a scan's returns placed in odom, off the robot's outline,
  and carried into the map, in one compiled pass.
- :mod:`perception.people.explained`: :class:`StaticScene`, which returns the map at patrol
  start and the known pots account for (and why not the live SLAM map).
- :mod:`perception.people.segments`: the scan split at range jumps into segments.
- :mod:`perception.people.shape`: a line and a circle fitted to every segment at once.
- :mod:`perception.people.legs`: leg arcs and pairs of legs by shape (a box corner is not one),
  the evidence the runtime counts per track (``mission.runtime.people``).
- :mod:`perception.people.bodies`: segments joined into bodies (legs paired within 0.8 m, a cart
  to its pusher), walls rejected by size, each body's shape scored.
- :mod:`perception.people.motion`: the constant-velocity Kalman filter, batched over tracks.
- :mod:`perception.people.tracker`: :class:`PersonTracker`, scan in, ``hw.people.Person`` out.
- :mod:`perception.people.config`: :class:`PeopleConfig`, every threshold and why.

The per-scan work (the scene lookup, segments, fits, bodies, leg shapes, the association and
the Kalman update) is compiled with numba, each module's kernel beside its idea: at the scan
rate the array versions' hundreds of small numpy calls cost three times the arithmetic
(``lupin bench perception.people`` at stop 63 on a quiet machine: 2.61-2.66 -> 0.72-0.93 ms a
scan median, the same tracks to 1e-14; at stop 64, the returns' passes and the tracker's step
compiled whole, 0.49-0.58 ms median and 0.78-0.81 ms p95).

Only hw/ is imported from below: the tracker hands its tracks down as ``hw.people.Person``. It
runs on the robot's CPU with no learned weights (the issue: nothing fetched at run time).
"""
from perception.people.config import PeopleConfig
from perception.people.explained import StaticScene, explained_mask
from perception.people.returns import odom_points
from perception.people.tracker import PersonTracker

__all__ = ["PeopleConfig", "PersonTracker", "StaticScene", "explained_mask", "odom_points"]
