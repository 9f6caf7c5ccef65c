"""Navigation: costmaps, NavFn planning, the MPPI Omni controller, the velocity smoother, the goal
checker and the navigator; SLAM and maps arrive with the SLAM issue."""
