"""Configuration of the costmaps (seed: "Costmaps for narrow aisles").

Both costmaps model the robot as a circle of ``robot_radius`` at ``resolution``; the inflation
is deliberately thin so ~0.8 m plant-row aisles stay drivable.
"""
from __future__ import annotations

from pydantic import Field

from hw.config import Strict


class CostmapsConfig(Strict):
    """The local and global costmaps."""

    resolution: float = Field(0.05, gt=0)
    """Cell size, m (seed: resolution 0.05 for both costmaps and the SLAM map)."""
    robot_radius: float = Field(0.22, gt=0)
    """Circular footprint radius, m (seed: robot_radius 0.22); the inscribed radius of inflation."""
    inflation_radius: float = Field(0.25, gt=0)
    """Inflation halo radius, m (seed: 0.25, ~0.03 m past the footprint; a textbook 0.55 m halo
    on a 0.22 m robot would close a 0.8 m aisle completely)."""
    cost_scaling_factor: float = Field(5.0, gt=0)
    """Exponential falloff of inflated cost (seed: 5.0, steep so the halo stays thin and MPPI
    keeps drivable space mid-aisle)."""
    obstacle_min_range: float = Field(0.25, ge=0)
    """Lidar returns closer than this are dropped, m (seed: 0.25 in both costmaps, AMCL and SLAM:
    the lidar sees the robot's own arm at ~0.10 m)."""
