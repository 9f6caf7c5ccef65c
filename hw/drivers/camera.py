"""USB / V4L2 cameras through OpenCV capture: the HAL's Camera, and JPEG for the link.

The seed's producer-side lesson: the vendor camera drivers ran at native rate whatever the
consumers needed, and two camera producers ate ~85 % of one A55 core; relaunching them at a
config-driven low rate cut that to ~15 %. So the rate is enforced *here, at the producer*:
the device is asked for the configured size and fps, and ``capture`` never reads the device
more often than ``fps`` (a faster caller gets the last frame again). Frames are resized to the
configured size if the device insists on another. ``jpeg`` encodes for the link: only JPEG
crosses the WiFi (seed: ~50 kB a frame at 30 fps is ~12 Mbps, raw would be ~220 Mbps).

``capture_factory`` is the boundary (``cv2.VideoCapture``); it also opens video files.
"""
from __future__ import annotations

import logging
import time
from typing import Callable

import cv2
import numpy as np

from hw.errors import InputError
from hw.interfaces import DeviceError

log = logging.getLogger(__name__)


def _source(device: str):
    return int(device) if device.isdigit() else device


def jpeg(frame: np.ndarray, quality: int = 80) -> bytes:
    ok, buf = cv2.imencode(".jpg", frame, [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
    if not ok:
        raise ValueError("JPEG encoding failed")
    return buf.tobytes()


class OpenCvCamera:
    def __init__(self, name: str, device: str, width: int, height: int, fps: float,
                 clock: Callable[[], float] = time.monotonic, capture_factory=cv2.VideoCapture):
        self.name, self.device = name, device
        self.width, self.height, self.fps = width, height, fps
        self.clock = clock
        self.cap = capture_factory(_source(device))
        if not self.cap.isOpened():
            raise InputError(f"camera {name} at {device}: cannot open")
        self.cap.set(cv2.CAP_PROP_FRAME_WIDTH, width)
        self.cap.set(cv2.CAP_PROP_FRAME_HEIGHT, height)
        self.cap.set(cv2.CAP_PROP_FPS, fps)
        self.cap.set(cv2.CAP_PROP_BUFFERSIZE, 1)
        self._last: np.ndarray | None = None
        self._t_last = -np.inf
        self.reads = 0

    def capture(self) -> np.ndarray:
        now = self.clock()
        if self._last is not None and now - self._t_last < 1.0 / self.fps:
            return self._last
        ok, frame = self.cap.read()
        if not ok or frame is None:
            raise DeviceError(f"camera {self.name} at {self.device}: no frame")
        self.reads += 1
        if frame.shape[:2] != (self.height, self.width):
            frame = cv2.resize(frame, (self.width, self.height), interpolation=cv2.INTER_AREA)
        self._last, self._t_last = frame, now
        return frame

    def close(self) -> None:
        self.cap.release()
