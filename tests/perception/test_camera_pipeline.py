"""The camera pipeline: captures only on request and never faster than the configured rate
(time from the runtime clock), JPEG for frames that leave the robot, device faults contained."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from hw.interfaces import DeviceError
from perception.camera_pipeline import CameraPipeline, decode_jpeg, encode_jpeg


class StepClock:
    def __init__(self):
        self.t = 0.0

    def now(self) -> float:
        return self.t

    def wait_until(self, t: float) -> None:
        self.t = max(self.t, t)


class CountingCamera:
    """A camera at the HAL boundary: counts captures, each frame carries its capture number."""

    width, height = 64, 48

    def __init__(self):
        self.captures = 0
        self.fault: Exception | None = None
        self.garbage = None

    def capture(self) -> np.ndarray:
        if self.fault is not None:
            raise self.fault
        if self.garbage is not None:
            return self.garbage
        self.captures += 1
        img = np.zeros((self.height, self.width, 3), np.uint8)
        img[:, :, 2] = self.captures
        return img


@pytest.fixture
def rig():
    cam, clock = CountingCamera(), StepClock()
    return cam, clock, CameraPipeline(cam, clock, max_rate=2.0, name="wrist")


def test_no_request_no_capture(rig):
    cam, clock, _ = rig
    clock.t = 100.0
    assert cam.captures == 0


def test_requests_faster_than_the_rate_reuse_the_last_frame(rig):
    cam, clock, pipe = rig
    got = []
    for k in range(41):  # 4 s of requests at 10 Hz against a 2 Hz cap
        clock.t = k * 0.1
        got.append(pipe.request())
    assert cam.captures == 9  # t = 0, 0.5, ..., 4.0
    assert [f.stamp for f in {id(f): f for f in got}.values()] == pytest.approx([0.5 * i for i in range(9)])
    assert got[3] is got[0] and got[5] is not got[4]
    assert int(got[-1].image[0, 0, 2]) == 9


def test_a_slow_consumer_gets_a_fresh_frame_each_time(rig):
    cam, clock, pipe = rig
    for k in range(5):
        clock.t = 3.0 * k
        frame = pipe.request()
        assert frame.stamp == clock.t
    assert cam.captures == 5


def test_fresh_waits_for_a_frame_after_a_given_time(rig):
    cam, clock, pipe = rig
    clock.t = 1.0
    pipe.request()
    clock.t = 1.2                       # the arm settled at 1.1: the 1.0 frame is stale,
    assert pipe.fresh(since=1.1) is None  # and the rate does not allow a new one yet
    clock.t = 1.5
    assert pipe.fresh(since=1.1).stamp == 1.5
    assert cam.captures == 2


def test_jpeg_is_encoded_once_and_decodes_to_the_frame():
    img = np.zeros((480, 640, 3), np.uint8)
    cv2.circle(img, (320, 240), 100, (40, 20, 220), -1)
    cam, clock = CountingCamera(), StepClock()
    cam.capture = lambda: img
    frame = CameraPipeline(cam, clock, 5.0, jpeg_quality=80).request()
    data = frame.jpeg
    assert data[:2] == b"\xff\xd8" and frame.jpeg is data
    assert len(data) < img.nbytes / 20  # what makes the link affordable (seed: ~50 kB vs 900 kB)
    back = decode_jpeg(data)
    assert back.shape == img.shape and np.abs(back.astype(int) - img).mean() < 2.0
    assert len(encode_jpeg(img, 30)) < len(encode_jpeg(img, 95))


def test_decode_rejects_non_images():
    assert decode_jpeg(b"") is None
    assert decode_jpeg(b"not a jpeg at all") is None


@pytest.mark.parametrize("fault", [DeviceError("usb camera gone"), OSError(19, "No such device")])
def test_a_failing_camera_gives_none_or_the_last_frame_and_keeps_its_rate(rig, fault):
    cam, clock, pipe = rig
    clock.t = 0.0
    first = pipe.request()
    cam.fault = fault
    clock.t = 1.0
    assert pipe.request() is first  # the last good frame, stamped when it was taken
    assert pipe.failures == 1
    clock.t = 1.2
    assert pipe.request() is first and pipe.failures == 1  # no retry inside the period


def test_garbage_frames_are_not_frames(rig):
    cam, clock, pipe = rig
    cam.garbage = np.zeros((0, 0), np.float32)
    assert pipe.request() is None and pipe.failures == 1
    cam.garbage = None
    clock.t = 0.5
    assert pipe.request().stamp == 0.5


def test_rate_must_be_positive():
    with pytest.raises(ValueError):
        CameraPipeline(CountingCamera(), StepClock(), 0.0)


def test_the_runtime_gets_one_pipeline_per_configured_camera():
    from perception.camera_pipeline import camera_pipelines
    from perception.config import PerceptionConfig

    config = PerceptionConfig.model_validate({"rates": {"front": 4.0, "wrist": 1.0}, "jpeg_quality": 60})
    cams = {"front": CountingCamera(), "wrist": CountingCamera(), "depth": CountingCamera()}
    pipes = camera_pipelines(cams, StepClock(), config)
    assert set(pipes) == {"front", "wrist"}
    assert pipes["front"].period == 0.25 and pipes["wrist"].period == 1.0 and pipes["wrist"].quality == 60
    assert pipes["front"].camera is cams["front"]
