"""The e-stop bridge, and the property that matters: the wheels stop on the next control tick."""
import logging
import random

import numpy as np
import pytest

from hw.config import EStopConfig, HwConfig
from hw.estop import EStopBridge, warn_unverified_polarity
from hw.interfaces import DeviceError, Twist
from tests.fixtures import FakeButton, make_base_rig, quiet_logger


def make(level=1, button_level=0):
    button = FakeButton(button_level)
    return EStopBridge(EStopConfig(engaged_level=level), button), button


@pytest.mark.parametrize("engaged_level", [0, 1])
def test_polarity_from_config(engaged_level):
    bridge, button = make(level=engaged_level, button_level=1 - engaged_level)
    assert not bridge.engaged()
    button.level = engaged_level
    assert bridge.engaged()


def test_the_bridge_itself_says_nothing_of_polarity(caplog):
    """The banner is the hardware backend's (tests/hw/test_backend.py): a sim has no pin to check."""
    with caplog.at_level(logging.WARNING):
        EStopBridge(EStopConfig(engaged_level=0), FakeButton(1))
    assert not [r for r in caplog.records if "POLARITY" in r.getMessage()]


def test_polarity_banner_is_loud(caplog):
    with caplog.at_level(logging.WARNING, logger="hw.estop"):
        warn_unverified_polarity(EStopConfig(engaged_level=0), logging.getLogger("hw.estop"))
    [record] = [r for r in caplog.records if r.name == "hw.estop"]
    assert record.levelno == logging.WARNING
    msg = record.getMessage()
    assert "UNVERIFIED" in msg and "level 0 means PRESSED" in msg
    assert "LUPIN_HW__ESTOP__ENGAGED_LEVEL=1" in msg


def test_button_is_read_live_not_from_last_publish():
    bridge, button = make()
    bridge.publish(0.0)
    button.level = 1
    assert bridge.engaged() and not bridge.state  # live before the 5 Hz publish catches up


def test_soft_stop_ors_with_button():
    bridge, button = make()
    bridge.set_soft(True)
    assert bridge.engaged()
    button.level = 1
    bridge.set_soft(False)
    assert bridge.engaged()
    button.level = 0
    assert not bridge.engaged()


def test_publish_records_changes_only_and_notifies_every_time():
    bridge, button = make()
    seen = []
    bridge.subscribe(lambda t, e: seen.append((t, e)))
    for k, level in enumerate([0, 0, 1, 1, 1, 0, 0]):
        button.level = level
        bridge.publish(k * 0.2)
    assert len(seen) == 7 and seen[2] == (0.4, True)
    assert bridge.events == [(0.4, True), (1.0, False)]
    assert bridge.state is False


@pytest.mark.parametrize("error", [DeviceError("gpio gone"), OSError(5, "EIO")])
def test_button_read_error_means_engaged_and_logs_once(caplog, error):
    bridge, button = make()
    button.error = error
    with caplog.at_level(logging.ERROR, logger="hw.estop"):
        assert bridge.engaged()
        assert bridge.engaged()
        bridge.publish(0.2)
    errors = [r for r in caplog.records if r.levelno >= logging.ERROR]
    assert len(errors) == 1 and "ENGAGED" in errors[0].getMessage()
    assert bridge.events == [(0.2, True)]
    button.error = None
    assert not bridge.engaged()


def test_button_read_error_stops_the_wheels():
    rig = make_base_rig(log=quiet_logger())
    rig.scheduler.run_until(0.1)
    rig.mux.publish("manual", Twist(0.2, 0, 0), 0.15)
    rig.scheduler.run_until(0.2)
    assert np.any(rig.base.last_duties != 0)
    rig.button.error = DeviceError("gpio gone")
    rig.scheduler.run_until(0.3)
    assert rig.duty_log[-1][0] == pytest.approx(0.3)
    assert np.all(rig.duty_log[-1][1] == 0)


def test_a_twist_sent_before_the_release_never_drives_after_it():
    """The autonomy's last command, still within its 0.5 s timeout at the release, is void: the
    wheels stay still until a source speaks again."""
    rig = make_base_rig(log=quiet_logger())
    rig.scheduler.run_until(0.1)
    rig.estop.set_soft(True)
    rig.mux.publish("auto", Twist(0.2, 0, 0), 0.15)
    rig.scheduler.run_until(0.2)
    rig.estop.set_soft(False)
    rig.scheduler.run_until(0.5)
    assert all(np.all(d == 0) for t, d in rig.duty_log if t > 0.15)
    rig.mux.publish("auto", Twist(0.2, 0, 0), 0.55)
    rig.scheduler.run_until(0.6)
    assert np.any(rig.base.last_duties != 0)


# -- the randomized property ------------------------------------------------------------------

SOURCES = ("joy", "manual", "auto")
TICK = 0.1


def _off_tick(t: float) -> float:
    """Nudge ``t`` off the 10 Hz grid so 'between ticks' is unambiguous."""
    frac = (t / TICK) % 1.0
    return t + 0.01 if frac < 1e-3 or frac > 1 - 1e-3 else t


def _random_twist(rng: random.Random) -> Twist:
    while True:
        t = Twist(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), rng.uniform(-1.0, 1.0))
        if abs(t.vx) + abs(t.vy) + abs(t.wz) > 0.05:
            return t


def run_trial(rng: random.Random, log) -> bool:
    """One trial; returns whether the base was driving just before the press."""
    level = rng.choice([0, 1])
    rig = make_base_rig(HwConfig(estop=EStopConfig(engaged_level=level)), log=log)
    duration = rng.uniform(3.0, 6.0)
    t_engage = _off_tick(rng.uniform(0.5, duration - 1.5))
    t_release = _off_tick(t_engage + rng.uniform(0.25, 1.0))
    soft = rng.random() < 0.5

    events = []  # (t, kind, payload)
    # autonomy streams the whole time at ~10 Hz with random jitter: a source is live after release
    t = rng.uniform(0.0, 0.1)
    while t < duration:
        events.append((t, "pub", ("auto", _random_twist(rng))))
        t += rng.uniform(0.05, 0.12)
    # bursts from the human sources at random times
    for _ in range(rng.randint(0, 4)):
        src = rng.choice(SOURCES[:2])
        t, end = rng.uniform(0.0, duration), 0.0
        end = t + rng.uniform(0.05, 1.0)
        while t < min(end, duration):
            events.append((t, "pub", (src, _random_twist(rng))))
            t += rng.uniform(0.03, 0.25)
    events.append((t_engage, "engage", None))
    events.append((t_release, "release", None))
    events.sort(key=lambda e: e[0])

    for t, kind, payload in events:
        rig.scheduler.run_until(t)
        if kind == "pub":
            rig.mux.publish(payload[0], payload[1], t)
        elif kind == "engage":
            if soft:
                rig.estop.set_soft(True)
            else:
                rig.button.level = level
        else:
            rig.estop.set_soft(False)
            rig.button.level = 1 - level
    rig.scheduler.run_until(duration)

    log_ = rig.duty_log
    before = [d for tt, d in log_ if tt < t_engage]
    during = [(tt, d) for tt, d in log_ if t_engage <= tt < t_release]
    after = [d for tt, d in log_ if tt >= t_release]
    assert during, "no control tick while engaged"
    assert during[0][0] - t_engage < TICK + 1e-9  # the very next tick...
    for tt, d in during:
        assert np.all(d == 0.0), (tt, d)  # ...and every one until release is exactly zero
    assert len(after) >= 3
    assert any(np.any(d != 0) for d in after[:2]), "did not resume after release"

    # the 5 Hz publish saw the press within one publish period and the release likewise
    (t_on, on), (t_off, off) = rig.estop.events
    assert on and not off
    assert 0 <= t_on - t_engage < 0.2 + 1e-9 and 0 <= t_off - t_release < 0.2 + 1e-9
    return bool(before) and bool(np.any(before[-1] != 0))


def test_estop_zeroes_duties_on_the_next_tick_randomized():
    rng = random.Random(20240527)
    log = quiet_logger("lupin.test.estop")
    driving = sum(run_trial(random.Random(rng.getrandbits(32)), log) for _ in range(200))
    assert driving >= 180  # the property was tested on a moving robot, not a parked one
