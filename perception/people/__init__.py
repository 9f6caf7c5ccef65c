"""perception.people: who stands or walks near the robot, from the lidar scan (issue 28 item 1).

A module per idea:

- :mod:`perception.people.config`: :class:`PeopleConfig`, the tracker's thresholds.
- :mod:`perception.people.tracker`: :class:`PersonTracker`, scan in, ``hw.people.Person`` out.

Only hw/ is imported from below: the tracker hands its tracks down as ``hw.people.Person``.
"""
from perception.people.config import PeopleConfig
from perception.people.tracker import PersonTracker

__all__ = ["PeopleConfig", "PersonTracker"]
