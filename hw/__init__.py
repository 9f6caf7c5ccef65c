"""Hardware: the HAL (``hw.interfaces``) and the services that run the same on the robot and
in the sim: twist_mux, e-stop bridge, base controller (mecanum + wheel PID + odometry),
controller manager, LED status. Device drivers (smbus2, pyserial, gpiod) come with a later issue.
"""
