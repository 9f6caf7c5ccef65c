"""The soft stop survives a restart (ISO 13850: a reset never restarts motion), and no twist sent
before a release drives the base after it."""
import json

from hw.config import EStopConfig, MuxConfig
from hw.estop import EStopBridge
from hw.interfaces import Twist
from hw.soft_stop_latch import LATCH, RUNNING, SoftStopLatch
from hw.twist_mux import IDLE, TwistMux
from tests.fixtures import FakeButton


def bridge(directory):
    return EStopBridge(EStopConfig(engaged_level=1), FakeButton(0), latch=SoftStopLatch(directory))


def test_a_first_start_is_released_and_marks_itself_running(tmp_path):
    b = bridge(tmp_path)
    assert not b.engaged() and b.held_since_start == ""
    assert (tmp_path / RUNNING).exists()
    b.close()
    assert not (tmp_path / RUNNING).exists()


def test_engaged_then_crash_comes_back_engaged_until_an_operator_releases(tmp_path):
    b = bridge(tmp_path)
    b.set_soft(True)
    assert json.loads((tmp_path / LATCH).read_text()) == {"engaged": True}
    del b  # the process dies: no close
    again = bridge(tmp_path)
    assert again.engaged()
    assert "engaged when the last runtime stopped" in again.held_since_start
    assert "did not exit cleanly" in again.held_since_start
    again.set_soft(False)
    assert not again.engaged() and again.held_since_start == ""
    again.close()
    assert not bridge(tmp_path).engaged()


def test_a_crash_with_the_stop_released_still_comes_back_engaged(tmp_path):
    bridge(tmp_path)  # runs, never closes (killed, power cut)
    b = bridge(tmp_path)
    assert b.engaged() and "did not exit cleanly" in b.held_since_start


def test_engaged_at_a_clean_exit_stays_engaged(tmp_path):
    b = bridge(tmp_path)
    b.set_soft(True)
    b.close()
    again = bridge(tmp_path)
    assert again.engaged() and "did not exit cleanly" not in again.held_since_start


def test_an_unreadable_latch_fails_safe(tmp_path):
    (tmp_path / LATCH).write_text("{not json")
    b = bridge(tmp_path)
    assert b.engaged() and "unreadable" in b.held_since_start


def test_no_twist_sent_before_a_release_drives_after_it():
    mux = TwistMux(MuxConfig())
    mux.publish("manual", Twist(vx=0.2), 1.0)
    mux.discard_until(1.1)  # the e-stop held at this tick
    assert mux.select(1.2) == (Twist(), IDLE)  # still within the source's timeout, but void
    mux.publish("manual", Twist(vx=0.1), 1.3)  # a fresh command after the release counts
    assert mux.select(1.3) == (Twist(vx=0.1), "manual")
