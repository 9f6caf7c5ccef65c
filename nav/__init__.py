"""Navigation: costmaps (``costmap/``), NavFn planning (``planner``), the MPPI Omni controller
(``mppi/``), the velocity smoother, the goal checker and the navigator; localisation by SLAM
(``slam/``, a worker process) or AMCL on a saved map (``amcl/``); maps in map_server format
(``occupancy``, ``map_io``, ``map_render``) and the one grid geometry they all share
(``grid_geometry``)."""
