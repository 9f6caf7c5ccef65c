import cv2
import numpy as np
import pytest

from hw.drivers.camera import OpenCvCamera, jpeg
from hw.drivers.led_strip import SpiLedStrip, decode_spi, encode_spi
from hw.errors import InputError
from hw.leds import to_wire


@pytest.fixture
def video(tmp_path):
    """A real capture source OpenCV can open here: a short MJPG file with numbered frames."""
    path = str(tmp_path / "cam.avi")
    w = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*"MJPG"), 30, (320, 240))
    for i in range(12):
        frame = np.full((240, 320, 3), 20 * i, np.uint8)
        w.write(frame)
    w.release()
    return path


def test_capture_never_reads_faster_than_configured(video):
    t = [0.0]
    cam = OpenCvCamera("front", video, 160, 120, fps=10.0, clock=lambda: t[0])
    a = cam.capture()
    assert a.shape == (120, 160, 3)  # resized to the configured size
    t[0] = 0.05
    assert cam.capture() is a and cam.reads == 1  # within 1/fps: the same frame, no device read
    t[0] = 0.1
    b = cam.capture()
    assert cam.reads == 2 and b.mean() > a.mean()
    cam.close()


def test_jpeg_roundtrip_is_small(video):
    cam = OpenCvCamera("wrist", video, 320, 240, fps=30.0)
    frame = cam.capture()
    data = jpeg(frame, 80)
    assert data[:2] == b"\xff\xd8" and len(data) < frame.nbytes / 10
    assert cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR).shape == frame.shape


def test_missing_camera_is_input_error(tmp_path):
    with pytest.raises(InputError, match="camera front"):
        OpenCvCamera("front", str(tmp_path / "video9"), 640, 480, 30)


def test_led_spi_encoding_roundtrip_in_wire_order(tmp_path):
    wire = to_wire([(255, 0, 0), (0, 10, 200)], "BRG")
    assert wire == bytes([0, 255, 0, 200, 0, 10])
    spi = encode_spi(wire)
    assert len(spi) == 3 * len(wire) + 90
    assert spi[:3] == bytes([0b10010010, 0b01001001, 0b00100100])  # 0x00 -> 100 x 8
    assert decode_spi(spi) == wire
    dev = tmp_path / "spidev"
    dev.write_bytes(b"")
    strip = SpiLedStrip(str(dev), num_leds=2)
    strip.write(wire)
    strip.close()
    assert decode_spi(dev.read_bytes()) == wire  # no reordering in the driver


def test_led_missing_device_is_input_error(tmp_path):
    with pytest.raises(InputError, match="LED strip"):
        SpiLedStrip(str(tmp_path / "nope" / "spidev"), 8)
