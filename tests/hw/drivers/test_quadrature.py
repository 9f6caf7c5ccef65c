from hypothesis import given, settings, strategies as st

from hw.drivers.button import GpioButton
from hw.drivers.quadrature import ILLEGAL, TABLE, QuadratureEncoders
from hw.emulators.gpio import EdgeEvent, EmulatedLineRequest

LINES = {"front_left": (0, 1), "front_right": (2, 3), "rear_left": (4, 5), "rear_right": (6, 7)}


def rig():
    req = EmulatedLineRequest(range(8))
    return req, QuadratureEncoders(req, LINES)


def test_table_is_the_reference_4x_table():
    assert list(TABLE) == [0, -1, 1, 0, 1, 0, 0, -1, -1, 0, 0, 1, 0, 1, -1, 0]
    assert [i for i in range(16) if ILLEGAL[i]] == [0b0011, 0b0110, 0b1001, 0b1100]


def test_counts_four_ticks_per_cycle_both_ways_per_wheel():
    req, enc = rig()
    req.turn(0, 1, 1320)  # one wheel revolution
    req.turn(2, 3, -37)
    req.turn(6, 7, 5)
    req.turn(6, 7, -2)
    assert enc.read_ticks() == (1320, -37, 0, 3)
    req.turn(0, 1, -20)
    assert enc.read_ticks() == (1300, -37, 0, 3)
    assert enc.lost.sum() == 0 and enc.illegal.sum() == 0


def test_lost_events_detected_from_seqno_and_the_count_recovers():
    req, enc = rig()
    req.turn(0, 1, 10)
    enc.read_ticks()
    req.lose(1)
    req.turn(0, 1, 10)  # the first edge's event is dropped by the "kernel"
    after_loss = enc.read_ticks()[0]
    assert enc.lost[0] >= 1  # detected (seqno gap / an edge to the level the line already had)
    # a lost edge also mislabels the other line's next edge: bounded by one cycle (4 ticks)
    assert 16 <= after_loss < 20
    req.turn(0, 1, 100)
    assert enc.read_ticks()[0] - after_loss == 100  # back in step with the pins
    assert enc.read_ticks()[1:] == (0, 0, 0)


def test_resync_after_a_loss_counts_a_two_bit_jump_as_illegal():
    req = EmulatedLineRequest(range(8))
    enc = QuadratureEncoders(req, LINES)
    rise = EdgeEvent.Type.RISING_EDGE
    req._events.append(EdgeEvent(rise, 1, 4, 1, 1))
    enc.read_ticks()  # rear_left A: 00 -> 10, +1
    # A rises again with a seqno gap (its fall was lost) while B glitched high: pins read 11
    req._events.append(EdgeEvent(rise, 2, 4, 3, 3))
    req.levels[4] = req.levels[5] = 1
    enc.read_ticks()
    assert enc.lost[2] == 2  # one duplicate edge + one seqno gap
    assert enc.illegal[2] == 0  # 10 -> 11 is one bit: recovered as a tick
    req._events.append(EdgeEvent(EdgeEvent.Type.FALLING_EDGE, 3, 5, 4, 5))  # B event, seqno gap
    req.levels[4], req.levels[5] = 0, 0  # but both pins now read low: 01 -> 00... from 11
    enc.state[2] = 0b11
    enc.read_ticks()
    assert enc.illegal[2] == 0
    req._events.append(EdgeEvent(rise, 4, 4, 5, 7))  # A rises after a gap; pins read 01
    req.levels[4], req.levels[5] = 0, 1
    enc.read_ticks()  # decoder 10 vs pins 01: both bits differ
    assert enc.illegal[2] == 1


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 7), st.integers(0, 1), st.integers(1, 5)), max_size=60))
def test_garbled_event_streams_never_raise(events):
    """Random edges on random lines, random seqno jumps: decoding degrades, never raises."""
    class Garbage(EmulatedLineRequest):
        pass

    req = Garbage(range(8))
    seqno = {o: 0 for o in range(8)}
    for i, (line, lvl, jump) in enumerate(events):
        seqno[line] += jump
        kind = EdgeEvent.Type.RISING_EDGE if lvl else EdgeEvent.Type.FALLING_EDGE
        req._events.append(EdgeEvent(kind, i, line, i, seqno[line]))
        req.levels[line] = lvl
    enc = QuadratureEncoders(EmulatedLineRequest(range(8)), LINES)
    enc.request = req
    enc.read_ticks()
    # and it is back in step: a clean turn after the garbage counts exactly
    before = enc.read_ticks()
    req.turn(0, 1, 8)
    assert enc.read_ticks()[0] - before[0] == 8


def test_button_level_and_short_press_latched():
    req = EmulatedLineRequest([8], {8: 0})
    button = GpioButton(req, 8, engaged_level=1)
    assert button.read_level() == 0
    req.set(8, 1)
    assert button.read_level() == 1
    req.set(8, 0)
    assert button.read_level() == 0
    req.set(8, 1)
    req.set(8, 0)  # a tap between two polls
    assert button.read_level() == 1 and button.presses == 2
    assert button.read_level() == 0


def test_button_active_low():
    req = EmulatedLineRequest([3], {3: 1})
    button = GpioButton(req, 3, engaged_level=0)
    req.set(3, 0)
    req.set(3, 1)
    assert button.read_level() == 0
    assert button.read_level() == 1
