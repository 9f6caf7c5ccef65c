import time

import pytest

from hw.drivers.hiwonder import HiwonderBus
from hw.drivers.hiwonder_protocol import Cmd, ERR_STALLED
from hw.emulators.hiwonder_bus import EmuServo, HiwonderBusEmulator
from hw.errors import InputError
from hw.interfaces import DeviceError


@pytest.fixture(params=[False, True], ids=["no-echo", "echo"])
def bus(request):
    with HiwonderBusEmulator() as emu:
        emu.faults.echo = request.param
        drv = HiwonderBus.open(emu.path, 115200, echo=request.param, timeout_s=0.2, retries=2)
        try:
            yield emu, drv
        finally:
            drv.close()


def sync(drv):
    """Writes have no reply: a read after them means the emulator has handled them."""
    drv.ping(2)


def test_move_sends_the_reference_packet_and_the_servo_gets_there(bus):
    emu, drv = bus
    drv.move(3, 500, 0)
    drv.move(3, 700, 0)
    assert drv.read_position(3) == 700
    assert emu.frames[0].encode() == bytes.fromhex("55 55 03 07 01 F4 01 00 00 FF")


def test_status_reads(bus):
    emu, drv = bus
    emu.servo(4).vin_mv, emu.servo(4).temperature_c = 11870, 41
    st = drv.read_status(4)
    assert (st.vin_mv, st.temperature_c, st.loaded) == (11870, 41, True)
    assert drv.read_move(4) == (500, 0)


def test_negative_position_reads_signed(bus):
    emu, drv = bus
    emu.servo(2).place(-12)
    assert drv.read_position(2) == -12


def test_offsets_adjust_write_read_without_the_community_bugs(bus):
    emu, drv = bus
    drv.adjust_offset(5, -5)
    assert drv.read_offset(5) == -5  # +255 mapping would read -6
    assert emu.servo(5).offset == -5
    assert emu.servo(5).saved_offset == 0  # adjust is 17 (volatile), not 18
    drv.write_offset(5)
    sync(drv)
    assert emu.servo(5).saved_offset == -5
    drv.adjust_offset(6, 125)
    assert drv.read_offset(6) == 125 and drv.read_offset(5) == -5  # id not swapped
    assert [f.cmd for f in emu.frames if f.servo_id == 5][:3] == [Cmd.ANGLE_OFFSET_ADJUST, Cmd.ANGLE_OFFSET_READ,
                                                                 Cmd.ANGLE_OFFSET_WRITE]
    with pytest.raises(ValueError):
        drv.adjust_offset(5, 126)


def test_offset_shifts_commands_and_reads(bus):
    emu, drv = bus
    drv.adjust_offset(2, 10)
    drv.move(2, 400, 0)
    sync(drv)
    assert emu.servo(2).position == pytest.approx(410)
    assert drv.read_position(2) == 400


def test_angle_limits_load_and_errors(bus):
    emu, drv = bus
    drv.write_angle_limits(3, 100, 900)
    assert drv.read_angle_limits(3) == (100, 900)
    drv.move(3, 950, 0)
    assert drv.read_position(3) == 900
    drv.set_load(3, False)
    assert drv.read_load(3) is False
    drv.set_load(3, True)
    sync(drv)
    emu.servo(3).stall()
    assert drv.read_errors(3) & ERR_STALLED
    assert drv.ping(3) and not drv.ping(9)


def test_echoed_request_is_never_taken_as_the_reply():
    """Echo on the wire but the driver configured without echo discarding: still correct."""
    with HiwonderBusEmulator() as emu:
        emu.faults.echo = True
        drv = HiwonderBus.open(emu.path, echo=False, timeout_s=0.1)
        emu.faults.silent = True
        with pytest.raises(DeviceError, match="servo id 2"):
            drv.read_position(2)  # only the echo comes back: a POS_READ with no params
        emu.faults.silent = False
        emu.servo(2).place(321)
        assert drv.read_position(2) == 321
        drv.close()


@pytest.mark.parametrize("fault", ["bad_checksum", "drop", "extra"])
def test_garbled_reply_is_retried(fault):
    with HiwonderBusEmulator() as emu:
        drv = HiwonderBus.open(emu.path, timeout_s=0.2, retries=2)
        emu.servo(6).place(250)
        setattr(emu.faults, fault, 1)
        assert drv.read_position(6) == 250
        assert drv.retried == (0 if fault == "extra" else 1)  # leading garbage is skipped, no retry
        drv.close()


def test_silent_servo_is_a_bounded_device_error():
    with HiwonderBusEmulator() as emu:
        drv = HiwonderBus.open(emu.path, timeout_s=0.02, retries=2)
        with pytest.raises(DeviceError, match="3 attempts"):
            drv.read_position(42)
        drv.close()
        sent = lambda: sum(1 for f in emu.frames if f.servo_id == 42)  # noqa: E731
        deadline = time.monotonic() + 2.0  # the emulator's thread reads the last frame in its own time
        while sent() < 3 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert sent() == 3


def test_wrong_port_is_input_error():
    with pytest.raises(InputError, match="/dev/nonexistent-tty"):
        HiwonderBus.open("/dev/nonexistent-tty")


def test_moving_servo_reads_intermediate_positions():
    with HiwonderBusEmulator({2: EmuServo(position=0, _target=0, _start=0)}) as emu:
        drv = HiwonderBus.open(emu.path)
        drv.move(2, 1000, 400)
        time.sleep(0.1)
        mid = drv.read_position(2)
        assert 0 < mid < 1000
        drv.close()
