"""The arm: the 4-DOF Hiwonder arm, its gripper and its wrist camera.

``limits`` (the joint windows and the gripper's sign, the single source of truth), ``presets``
(named poses), ``servo_interface`` (the vendor's dead-band re-assert write loop and the startup
pin), ``trajectory`` and ``controller`` (the 10 Hz trajectory controller the runtime schedules),
``gripper`` (operator degrees -> gripper goal -> reached / stalled), ``stall`` (shoulder_lift's
unload and latch), ``calibration`` (zero offsets, hardware only), ``kinematics`` and ``aim``
(wrist-camera forward kinematics and casadi camera aiming).
"""
