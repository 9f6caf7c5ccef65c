"""Device emulators: the last boundary that cannot run here, emulated at register / byte level.

The drivers in ``hw/drivers`` are tested against these, never against mocks of themselves:

* ``i2c_bus.I2cBusTwin`` is an smbus2-compatible bus object; the register-level twins of the
  PCA9685, INA226, MPU9250 (+ AK8963), AS5600 and the TCA9548A mux hang on it.
* ``gpio.EmulatedLineRequest`` stands in for a libgpiod v2 line request (edge events with
  sequence numbers, line values) for the wheel encoders and the e-stop button.
* ``hiwonder_bus`` and ``rplidar`` serve the Hiwonder servo bus and the RPLidar C1 on a real
  pseudo-terminal (``os.openpty``) that pyserial opens like the USB adapter, speaking the byte
  protocol from a thread, with fault injection (bad checksums, dropped and extra bytes, echo,
  silence).
"""
