"""Camera frames on request, never faster than configured, JPEG for anything leaving the robot.

The seed's producer-side lesson: the vendor drivers ran both cameras at their native 30 fps
whatever anyone needed, and the two producers alone ate ~85 % of one core; the fix was to
produce at a configured low rate rather than throttle downstream. So a :class:`CameraPipeline`
captures only when a consumer asks (:meth:`request`), and a request that comes sooner than
``1 / max_rate`` after the last capture gets that same frame back instead of a new capture.

The second lesson: only JPEG crosses the link (640x480 BGR at 30 fps is ~220 Mbit/s against
~60 usable on the robot's access point; JPEG is ~50 kB a frame). :attr:`Frame.jpeg` encodes
once, on first use, at the configured quality.

Time comes from the runtime clock passed in (sim or wall), never from ``time``. A camera that
raises or returns garbage gives ``None`` (and counts a failure), never an exception.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass
from functools import cached_property

import cv2
import numpy as np

from hw.interfaces import Camera, Clock, DeviceError
from perception.frames import as_bgr

log = logging.getLogger(__name__)


def encode_jpeg(image: np.ndarray, quality: int) -> bytes:
    """JPEG bytes of a BGR uint8 image."""
    ok, buf = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
    if not ok:
        raise ValueError(f"could not JPEG-encode a {image.shape} {image.dtype} image")
    return buf.tobytes()


def decode_jpeg(data: bytes) -> np.ndarray | None:
    """BGR uint8 image of JPEG (or PNG) bytes, or None if they are not an image."""
    if not data:
        return None
    return cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)


@dataclass(frozen=True)
class Frame:
    """One captured frame: BGR uint8 pixels and the runtime time it was taken."""

    stamp: float
    image: np.ndarray
    camera: str
    quality: int = 80

    @cached_property
    def jpeg(self) -> bytes:
        """The frame as JPEG (encoded once, on first use): the only form that leaves the robot."""
        return encode_jpeg(self.image, self.quality)


class CameraPipeline:
    """Frames from one HAL camera, on request, at most ``max_rate`` captures per second."""

    def __init__(self, camera: Camera, clock: Clock, max_rate: float, name: str = "camera",
                 jpeg_quality: int = 80):
        if max_rate <= 0:
            raise ValueError(f"max_rate must be positive, got {max_rate}")
        self.camera, self.clock, self.name = camera, clock, name
        self.period = 1.0 / max_rate
        self.quality = jpeg_quality
        self.captures = 0
        self.failures = 0
        self._last: Frame | None = None
        self._last_attempt: float | None = None

    @property
    def last(self) -> Frame | None:
        return self._last

    def request(self) -> Frame | None:
        """The newest frame: a fresh capture if the rate allows one now, else the last frame.

        ``None`` until a capture has succeeded. A failed capture also uses up its slot, so a
        broken camera is not hammered at the consumers' rate either.
        """
        now = self.clock.now()
        if self._last_attempt is not None and now - self._last_attempt < self.period - 1e-9:
            return self._last
        self._last_attempt = now
        try:
            image = as_bgr(self.camera.capture())
        except (DeviceError, OSError) as exc:  # a device fault must not reach the control loop
            log.warning("%s camera: capture failed: %s", self.name, exc)
            image = None
        if image is None:
            self.failures += 1
            return self._last
        self.captures += 1
        self._last = Frame(now, image, self.name, self.quality)
        return self._last

    def fresh(self, since: float) -> Frame | None:
        """A frame taken at or after ``since`` (e.g. after the arm settled), or None yet."""
        frame = self.request()
        return frame if frame is not None and frame.stamp >= since else None


def camera_pipelines(cameras: dict[str, Camera], clock: Clock, config) -> dict[str, CameraPipeline]:
    """One pipeline per HAL camera that has a rate in ``config`` (a PerceptionConfig): the
    runtime's single place where cameras get their producer-side caps."""
    rates = config.rates.model_dump()
    return {name: CameraPipeline(cam, clock, rates[name], name, config.jpeg_quality)
            for name, cam in cameras.items() if name in rates}
