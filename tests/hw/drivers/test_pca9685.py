import pytest

from hw.drivers.hbridge import HBridgeWheels
from hw.drivers.pca9685 import Pca9685, channel_bytes, prescale_for
from hw.emulators.i2c_bus import I2cBusTwin
from hw.emulators.pca9685 import Pca9685Twin
from hw.errors import InputError
from hw.interfaces import DeviceError

CHANNELS = {"front_left": (2, 3), "front_right": (1, 0), "rear_left": (6, 7), "rear_right": (5, 4)}


def STILL() -> float:
    """A clock for wheels no watchdog watches here."""
    return 0.0


def rig(**kw):
    bus = I2cBusTwin()
    twin = bus.attach(0x41, Pca9685Twin())
    sleeps: list[float] = []
    pwm = Pca9685(bus, 0x41, sleep=sleeps.append)
    return bus, twin, pwm, sleeps


def test_prescale_formula_has_the_minus_one_and_clamps():
    assert prescale_for(50) == 121  # 25e6 / (4096*50) = 122.07 -> 122 - 1
    assert prescale_for(100) == 60
    assert prescale_for(1526) == 3 and prescale_for(5000) == 3
    assert prescale_for(24) == 253 and prescale_for(1) == 255


def test_frequency_sequence_latches_prescale_and_restarts():
    _, twin, pwm, sleeps = rig()
    pwm.start(100)
    assert twin.regs[0xFE] == 60
    assert twin.rejected_prescale_writes == 0
    assert not twin.asleep
    assert twin.regs[0x00] & 0x20  # auto-increment on
    assert twin.frequency() == pytest.approx(100, rel=0.02)
    assert sleeps and min(sleeps) >= 0.0005


def test_a_prescale_written_awake_is_ignored_by_the_twin():
    bus, twin, pwm, _ = rig()
    pwm.start(100)
    bus.write_byte_data(0x41, 0xFE, 10)
    assert twin.rejected_prescale_writes == 1 and twin.regs[0xFE] == 60


def test_duty_maps_linearly_and_uses_full_bits_at_the_ends():
    _, twin, pwm, _ = rig()
    pwm.start(100)
    pwm.set_duty(5, 0.5)
    assert twin.duty(5) == pytest.approx(0.5, abs=1 / 4096)
    pwm.set_duty(5, 1.0)
    assert twin.duty(5) == 1.0 and twin.regs[0x06 + 4 * 5 + 1] == 0x10
    pwm.set_duty(5, 0.0)
    assert twin.duty(5) == 0.0 and twin.regs[0x06 + 4 * 5 + 3] == 0x10
    assert channel_bytes(float("nan")) == [0, 0, 0, 0x10]


def test_all_off_silences_every_output():
    _, twin, pwm, _ = rig()
    pwm.start(100)
    for ch in range(16):
        pwm.set_duty(ch, 0.3)
    pwm.all_off()
    assert twin.duties() == [0.0] * 16


def test_missing_chip_is_one_clear_input_error():
    bus = I2cBusTwin()
    with pytest.raises(InputError, match="PCA9685.*0x41"):
        Pca9685(bus, 0x41).start(100)


def test_nack_while_running_is_a_device_error():
    _, twin, pwm, _ = rig()
    pwm.start(100)
    twin.present = False
    with pytest.raises(DeviceError):
        pwm.set_duty(0, 0.5)


def test_hbridge_forward_on_a_reverse_on_b():
    _, twin, pwm, _ = rig()
    pwm.start(100)
    wheels = HBridgeWheels(pwm, CHANNELS, clock=STILL)
    wheels.set_duties([0.5, -0.25, 1.0, 0.0])
    d = twin.duties()
    assert d[2] == pytest.approx(0.5, abs=1e-3) and d[3] == 0.0  # front_left A/B
    assert d[1] == 0.0 and d[0] == pytest.approx(0.25, abs=1e-3)  # front_right reverse on B
    assert d[6] == 1.0 and d[7] == 0.0
    assert d[5] == 0.0 and d[4] == 0.0


def test_hbridge_reversal_zeroes_both_channels_for_the_pause_first():
    bus, twin, pwm, sleeps = rig()
    pwm.start(100)
    wheels = HBridgeWheels(pwm, CHANNELS, reversal_pause_s=0.010, sleep=sleeps.append, clock=STILL)
    wheels.set_duties([0.5, 0.5, 0.5, 0.5])
    sleeps.clear()
    seen = []
    wheels._sleep = lambda s: (sleeps.append(s), seen.append((twin.duty(2), twin.duty(3), twin.duty(1))))
    wheels.set_duties([-0.5, 0.5, 0.5, 0.5])
    assert sleeps == [0.010]
    assert seen == [(0.0, 0.0, pytest.approx(0.5, abs=1e-3))]  # reversing wheel at zero, others untouched
    assert twin.duty(3) == pytest.approx(0.5, abs=1e-3) and twin.duty(2) == 0.0
    assert wheels.reversals == 1
    wheels.set_duties([-0.2, 0.5, 0.5, 0.5])  # same direction: no pause
    assert sleeps == [0.010]


def test_hbridge_inhibit_turns_every_output_off():
    _, twin, pwm, _ = rig()
    pwm.start(100)
    pressed = [False]
    pwm.set_duty(15, 0.7)  # a non-wheel channel
    wheels = HBridgeWheels(pwm, CHANNELS, inhibit=lambda: pressed[0], clock=STILL)
    wheels.set_duties([0.5] * 4)
    pressed[0] = True
    wheels.set_duties([0.9] * 4)
    assert twin.duties() == [0.0] * 16 and wheels.inhibited
    pressed[0] = False
    wheels.set_duties([0.4] * 4)
    assert twin.duty(2) == pytest.approx(0.4, abs=1e-3)


def test_hbridge_non_finite_duty_is_zero():
    _, twin, pwm, _ = rig()
    pwm.start(100)
    HBridgeWheels(pwm, CHANNELS, clock=STILL).set_duties([float("nan"), float("inf"), 0.3, 0.3])
    assert twin.duty(2) == 0.0 and twin.duty(3) == 0.0
    assert twin.duty(1) == 0.0 and twin.duty(0) == 0.0  # inf is garbage too, not full speed
    assert twin.duty(6) == pytest.approx(0.3, abs=1e-3)
