"""Configuration of the costmaps (seed: "Costmaps for narrow aisles")."""
from __future__ import annotations

from hw.config import Strict


class CostmapsConfig(Strict):
    """The local and global costmaps."""
