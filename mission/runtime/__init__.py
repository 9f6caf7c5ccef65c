"""The runtime: config, the scheduler, the robot assembly (hardware services, the arm,
navigation) on a HAL, the sim runtime, and the boot heal."""
