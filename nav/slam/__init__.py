"""SLAM: lidar odometry, an occupancy grid, loop closure and a pose graph, in a worker process.

Read it like a table of contents (``nav.slam.mapper.Mapper``): a scan becomes points
(``scan_points``), is registered against a local voxel map with wheel odometry as the guess
(``lidar_odometry``), is rendered into a log-odds grid (``grid``); every ``keyframe_distance``
the scan is kept as a node of a pose graph (``pose_graph``), whose revisits are found and
matched (``loop_closure``) and optimised with casadi, after which the grid is re-rendered from
the corrected keyframes. The pipeline runs in its own process (``worker``) that the runtime
supervises and respawns (``supervisor``), as the original ran slam_toolbox as a respawning node;
a respawned worker goes on from the state the supervisor keeps (``checkpoint``), not an empty map.
"""
