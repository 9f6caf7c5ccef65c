"""Frame hygiene shared by the detectors: whatever a device or a file hands over, a detector
either gets a contiguous uint8 BGR image it can work on or nothing at all.

Garbage from a device must never crash a control loop (DESIGN.md), so an empty array, a float
image, a wrong shape or None all come back as ``None`` and the detector reports no detection.
"""
from __future__ import annotations

import cv2
import numpy as np


def as_bgr(frame: object) -> np.ndarray | None:
    """A uint8 HxWx3 BGR view/copy of ``frame`` (grey and BGRA are converted), or None."""
    if not isinstance(frame, np.ndarray) or frame.dtype != np.uint8 or frame.size == 0:
        return None
    if frame.ndim == 2:
        return cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR)
    if frame.ndim != 3 or frame.shape[0] < 8 or frame.shape[1] < 8:
        return None
    if frame.shape[2] == 3:
        return np.ascontiguousarray(frame)
    if frame.shape[2] == 4:
        return cv2.cvtColor(frame, cv2.COLOR_BGRA2BGR)
    return None


def as_gray(frame: object) -> np.ndarray | None:
    """A uint8 HxW grey image of ``frame``, or None (see :func:`as_bgr`)."""
    if isinstance(frame, np.ndarray) and frame.dtype == np.uint8 and frame.ndim == 2 and min(frame.shape) >= 8:
        return np.ascontiguousarray(frame)
    bgr = as_bgr(frame)
    return None if bgr is None else cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY)


def fit_width(image: np.ndarray, width: int) -> tuple[np.ndarray, float]:
    """``image`` shrunk (never enlarged) so it is at most ``width`` wide, and the factor that
    turns its pixel coordinates back into the original's. A phone photo is 4000 px wide; the
    detectors' pixel thresholds are for 640 px frames."""
    w = image.shape[1]
    if w <= width:
        return image, 1.0
    scale = w / width
    h = max(1, round(image.shape[0] / scale))
    return cv2.resize(image, (width, h), interpolation=cv2.INTER_AREA), scale
