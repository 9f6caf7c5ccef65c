"""The console's gamepad on a virtual event stream: kernel ``input_event`` records written into a
pipe, read by the same code that reads ``/dev/input/eventN``. The dead-man gates every twist, a
release sends one zero at once, a pad that goes away counts as released; and on a real sim
runtime the pad drives as ``joy``, its release zeroes the robot's joy twist inside one beat of
the mux's timeout, and a lost link leaves the mux to time it out."""
from __future__ import annotations

import os
import threading
import time

import pytest

from hw.interfaces import ZERO_TWIST
from tests.link.sim_service import client, runtime, wait_for  # noqa: F401  (runtime: the fixture)
from tui.gamepad import ABS_RX, ABS_X, ABS_Y, BTN_TL, EV_ABS, EV_KEY, EVENT, SPEED, TURN, Gamepad

SYN = (0, 0, 0)


def record(*events: tuple[int, int, int]) -> bytes:
    """Kernel input_event records, each followed by a SYN_REPORT as a pad sends them."""
    out = b""
    for etype, code, value in events:
        out += EVENT.pack(1, 0, etype, code, value) + EVENT.pack(1, 0, *SYN)
    return out


class Sent:
    def __init__(self):
        self.twists: list[tuple[float, float, float, str]] = []
        self.lock = threading.Lock()

    def __call__(self, command, /, **args):
        assert command == "teleop"
        with self.lock:
            self.twists.append((args["vx"], args["vy"], args["wz"], args["source"]))
        return None


@pytest.fixture
def pad():
    r, w = os.pipe()
    sent = Sent()
    g = Gamepad(r, sent).start()
    try:
        yield g, w, sent
    finally:
        g.close()
        for fd in (r, w):
            try:
                os.close(fd)
            except OSError:
                pass


def test_nothing_drives_without_the_dead_man_and_a_release_sends_one_zero(pad):
    g, w, sent = pad
    os.write(w, record((EV_ABS, ABS_Y, -32767), (EV_ABS, ABS_X, 32767), (EV_ABS, ABS_RX, -16384)))
    time.sleep(0.3)
    assert sent.twists == []  # sticks pushed, dead-man up: nothing
    data = record((EV_KEY, BTN_TL, 1))
    os.write(w, data[:10])  # a record split across reads is still one record
    os.write(w, data[10:])
    assert wait_for(lambda: len(sent.twists) >= 4, 2.0)
    vx, vy, wz, source = sent.twists[-1]
    assert (vx, vy, source) == (SPEED, -SPEED, "joy") and wz == pytest.approx(0.5 * TURN, abs=0.01)
    os.write(w, record((EV_ABS, ABS_X, 1000)))  # inside the dead zone: no strafe
    assert wait_for(lambda: sent.twists[-1][1] == 0.0, 2.0)
    os.write(w, record((EV_KEY, BTN_TL, 0)))
    assert wait_for(lambda: sent.twists[-1][:3] == (0.0, 0.0, 0.0), 1.0)
    n = len(sent.twists)
    time.sleep(0.3)
    assert len(sent.twists) == n  # one zero, then silence: the mux hands the bus back


def test_a_pad_that_goes_away_while_held_counts_as_released(pad):
    g, w, sent = pad
    os.write(w, record((EV_KEY, BTN_TL, 1), (EV_ABS, ABS_Y, -32767)))
    assert wait_for(lambda: sent.twists and sent.twists[-1][0] == SPEED, 2.0)
    os.close(w)  # unplugged: the stream ends
    assert wait_for(lambda: sent.twists[-1][:3] == (0.0, 0.0, 0.0), 1.0)


@pytest.mark.slow
def test_on_a_real_runtime_the_pad_drives_as_joy_and_its_release_zeroes_the_twist_at_once(runtime):
    service = runtime.service
    mux = service.robot.mux
    console = client(runtime.endpoint)
    r, w = os.pipe()
    g = Gamepad(r, console.send).start()
    try:
        os.write(w, record((EV_KEY, BTN_TL, 1), (EV_ABS, ABS_RX, -32767)))
        assert wait_for(lambda: mux.active_source(service.now) == "joy", 10)
        assert wait_for(lambda: service.robot.base.last_duties.any(), 10)  # the wheels turn
        released_at = service.now
        os.write(w, record((EV_KEY, BTN_TL, 0)))
        assert wait_for(lambda: mux.last("joy")[1] == ZERO_TWIST, 5)
        stamp = mux.last("joy")[0]
        # the zero is there before the mux's 0.3 s timeout would have stopped the wheels
        assert stamp - released_at < 0.3, f"the release's zero reached the robot {stamp - released_at:.3f} s after"
        os.write(w, record((EV_KEY, BTN_TL, 1)))
        assert wait_for(lambda: mux.last("joy")[1] != ZERO_TWIST, 5)
        console.close()  # the link lost while the dead-man is held
        moving = mux.last("joy")[1]
        assert wait_for(lambda: mux.active_source(service.now) != "joy", 5)  # the mux timed it out
        assert moving != ZERO_TWIST
    finally:
        g.close()
        os.close(w)
        os.close(r)
