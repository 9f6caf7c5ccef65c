"""Configuration of the lidar person tracker (``perception.people``)."""
from __future__ import annotations

from hw.config import Strict


class PeopleConfig(Strict):
    """The person tracker on the lidar scan."""
