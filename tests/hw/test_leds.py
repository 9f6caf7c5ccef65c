import numpy as np
import pytest

from hw.config import LedConfig
from hw.interfaces import DeviceError
from hw.leds import PALETTE, LedStatus, pick_state, to_wire
from tests.fixtures import FakeStrip


def test_brg_and_grb_on_the_wire():
    px = [(10, 20, 30)]  # r, g, b all different: every order gives different bytes
    assert to_wire(px, "BRG") == bytes([30, 10, 20])
    assert to_wire(px, "GRB") == bytes([20, 10, 30])
    assert to_wire(px, "RGB") == bytes([10, 20, 30])
    assert to_wire([(255, 0, 0)], "BRG") == bytes([0x00, 0xFF, 0x00])  # red in slot 1 (seed)


def test_order_applies_per_pixel_and_accepts_arrays():
    px = np.array([[1, 2, 3], [4, 5, 6]], dtype=np.int64)
    assert to_wire(px, "brg") == bytes([3, 1, 2, 6, 4, 5])
    assert to_wire([], "GRB") == b""


@pytest.mark.parametrize("bad", [[(256, 0, 0)], [(-1, 0, 0)], [(0.5, 0, 0)]])
def test_rejects_out_of_range_pixels(bad):
    with pytest.raises(ValueError):
        to_wire(bad, "RGB")


def test_rejects_bad_order():
    with pytest.raises(ValueError):
        to_wire([(1, 2, 3)], "RRB")


def test_palette_states_distinct_and_estop_red():
    assert set(PALETTE) == {
        "standby", "driving", "arm_moving", "estop", "mission_running",
        "mission_paused", "mission_done", "mission_failed", "battery_low",
    }
    assert len(set(PALETTE.values())) == len(PALETTE)
    assert PALETTE["estop"] == (255, 0, 0)
    assert all(0 <= c <= 255 for rgb in PALETTE.values() for c in rgb)


def test_status_writes_whole_strip_in_config_order():
    strip = FakeStrip(5)
    leds = LedStatus(LedConfig(color_order="BRG", num_leds=5), strip)
    assert leds.show("estop")
    assert strip.writes == [bytes([0, 255, 0]) * 5]
    leds.show("mission_paused")  # amber (255, 160, 0) -> BRG 0, 255, 160
    assert strip.writes[-1] == bytes([0, 255, 160]) * 5


def test_status_writes_only_on_change():
    strip = FakeStrip(8)
    leds = LedStatus(LedConfig(color_order="GRB"), strip)
    for state in ["standby", "standby", "driving", "driving", "driving", "standby"]:
        leds.show(state)
    assert len(strip.writes) == 3
    assert leds.state == "standby"


def test_unknown_state_rejected():
    with pytest.raises(ValueError, match="unknown LED state"):
        LedStatus(LedConfig(), FakeStrip()).show("disco")


def test_failed_write_is_retried():
    class Flaky(FakeStrip):
        fail = True

        def write(self, wire):
            if self.fail:
                raise DeviceError("SPI busy")
            super().write(wire)

    strip = Flaky(8)
    leds = LedStatus(LedConfig(), strip)
    assert not leds.show("driving") and leds.state is None
    strip.fail = False
    assert leds.show("driving") and len(strip.writes) == 1


def test_pick_state_precedence():
    assert pick_state() == "standby"
    assert pick_state(estop=True, battery_low=True, driving=True) == "estop"
    assert pick_state(battery_low=True, mission="failed") == "battery_low"
    assert pick_state(mission="paused", driving=True) == "mission_paused"
    assert pick_state(mission="running", driving=True) == "driving"
    assert pick_state(mission="running", arm_moving=True, driving=True) == "arm_moving"
    assert pick_state(mission="running") == "mission_running"
    with pytest.raises(ValueError):
        pick_state(mission="dancing")
