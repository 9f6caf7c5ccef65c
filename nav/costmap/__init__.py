"""Costmaps (seed: "Costmaps for narrow aisles"): 0.05 m cost grids in Nav2's values, one layer
per module, merged by the layered costmap.

- ``grid``: ``CostGrid``, the grid type every layer, the planner and the critics share;
- ``obstacle`` (+ ``raytrace``): lidar returns mark, beams clear;
- ``inflation``: Nav2's exponential halo (robot radius 0.22, inflation 0.25, scaling 5.0);
- ``static``: a map_server occupancy map as costs;
- ``people``: tracked people's keep-out (0.3 m body to body), falloff and walking stretch;
- ``robots``: the fleet's other robots' footprints, where each says it is;
- ``layered``: ``Costmap`` and its factories ``local_costmap`` (3 x 3 m rolling window, odom)
  and ``global_costmap`` (fixed extent, map frame, tracks unknown space).
"""
