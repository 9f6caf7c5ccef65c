"""Hardware: the HAL (``hw.interfaces``) and the services that run the same on the robot and
in the sim: twist_mux, e-stop bridge, base controller (mecanum + wheel PID + odometry),
controller manager, LED status; the device drivers (``hw.drivers``: smbus2, pyserial, gpiod,
OpenCV capture), their emulators for tests off the robot (``hw.emulators``), and the hardware
backend that assembles the HAL from the drivers (``hw.backend``).
"""
