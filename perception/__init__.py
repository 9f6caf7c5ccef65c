"""perception: what the robot sees at a pot.

- :mod:`perception.flower_detector`: the HSV flower detector on wrist-camera frames (classes
  red / white / pink, the dark pest spot, morphology, minimum blob area) -> :class:`FlowerFrame`.
- :mod:`perception.tag_reader`: the AprilTag 36h11 reader on front-camera frames (id whitelist,
  solvePnP pose with the camera's intrinsics, off-axis angle) -> tuple of :class:`TagRead`.
- :mod:`perception.camera_pipeline`: frames on request at most at the configured rate, JPEG
  for anything that leaves the robot.
- :mod:`perception.detections`: the frozen records the mission stores.
- :mod:`perception.evaluation`: scoring against truth (the sim harness is
  ``lupin/bench/perception.py``); :mod:`perception.annotate`: drawing for ``lupin detect``.

Only hw/ is imported from below (the HAL's Camera and Clock, the camera matrix).
"""
from perception.camera_pipeline import CameraPipeline, Frame
from perception.detections import Bloom, FlowerFrame, TagRead
from perception.flower_detector import FlowerDetector
from perception.tag_reader import TagReader

__all__ = ["Bloom", "CameraPipeline", "FlowerDetector", "FlowerFrame", "Frame", "TagRead", "TagReader"]
