"""Pinhole camera matrix from an image size and a vertical field of view.

Lives in hw/ because two layers need it: the sim renders its cameras from a field of view
(MuJoCo ``fovy``), and perception reads tag poses with a camera matrix. An ideal renderer has
square pixels and its principal point in the image centre; in OpenCV's convention pixel
``i`` is centred at ``i``, so the centre of a W-pixel row is at (W - 1) / 2.
"""
from __future__ import annotations

import math

import numpy as np


def camera_matrix(width: int, height: int, fovy_deg: float) -> np.ndarray:
    """3x3 K (float64) for a ``width`` x ``height`` image with vertical FOV ``fovy_deg``."""
    if width <= 0 or height <= 0 or not 0 < fovy_deg < 180:
        raise ValueError(f"need a positive size and 0 < fovy < 180 deg, got {width}x{height}, {fovy_deg}")
    f = (height / 2.0) / math.tan(math.radians(fovy_deg) / 2.0)
    return np.array([[f, 0.0, (width - 1) / 2.0], [0.0, f, (height - 1) / 2.0], [0.0, 0.0, 1.0]])
