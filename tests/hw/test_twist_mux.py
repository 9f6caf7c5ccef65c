"""The seed's twist_mux table: joy 100/0.3 s, manual 50/0.5 s, auto 10/0.5 s, idle zero guard."""
import pytest

from hw.config import MuxConfig, MuxSource
from hw.interfaces import ZERO_TWIST, Twist
from hw.twist_mux import IDLE, TwistMux

JOY, MANUAL, AUTO = Twist(0.5, 0, 0), Twist(0, 0.3, 0), Twist(0.2, 0, 0.4)


@pytest.fixture
def mux():
    return TwistMux(MuxConfig())


def test_idle_guard_when_nothing_ever_published(mux):
    assert mux.select(0.0) == (ZERO_TWIST, IDLE)
    assert mux.active_source(123.0) == IDLE


@pytest.mark.parametrize(
    "source, twist, timeout", [("joy", JOY, 0.3), ("manual", MANUAL, 0.5), ("auto", AUTO, 0.5)]
)
def test_each_source_alone_and_its_timeout_boundary(mux, source, twist, timeout):
    mux.publish(source, twist, now=10.0)
    assert mux.select(10.0) == (twist, source)
    assert mux.select(10.0 + timeout / 2) == (twist, source)
    assert mux.select(10.0 + timeout) == (twist, source)  # age == timeout still counts
    assert mux.select(10.0 + timeout + 1e-9) == (ZERO_TWIST, IDLE)  # strictly older is dead


def test_boundary_with_float_times(mux):
    # 1.3 - 1.0 > 0.3 in floats; ages are compared on the scheduler's nanosecond grid
    assert 1.3 - 1.0 > 0.3
    mux.publish("joy", JOY, 1.0)
    assert mux.active_source(1.3) == "joy"
    assert mux.active_source(1.3 + 1e-9) == IDLE


def test_priority_order_when_all_live(mux):
    mux.publish("auto", AUTO, 0.0)
    mux.publish("manual", MANUAL, 0.0)
    mux.publish("joy", JOY, 0.0)
    assert mux.select(0.1) == (JOY, "joy")


def test_higher_source_preempts_immediately(mux):
    mux.publish("auto", AUTO, 0.0)
    assert mux.active_source(0.05) == "auto"
    mux.publish("manual", MANUAL, 0.1)
    assert mux.select(0.1) == (MANUAL, "manual")
    mux.publish("auto", AUTO, 0.15)  # a lower source talking does not take the bus back
    assert mux.active_source(0.15) == "manual"
    mux.publish("joy", JOY, 0.2)
    assert mux.active_source(0.2) == "joy"


def test_lower_source_regains_bus_after_higher_times_out(mux):
    owners = {}
    for k in range(30):  # autonomy streams at 10 Hz for 3 s; one dead-man message at 1.0 s
        t = k * 0.1
        mux.publish("auto", Twist(0.1 * (k % 3), 0, 0), t)
        if k == 10:
            mux.publish("joy", JOY, t)
        owners[k] = mux.select(t)
    assert [owners[k][1] for k in range(9, 15)] == ["auto", "joy", "joy", "joy", "joy", "auto"]
    assert owners[14] == (Twist(0.1 * (14 % 3), 0, 0), "auto")  # auto's latest, not a stale one


def test_cascade_joy_manual_auto_idle(mux):
    mux.publish("auto", AUTO, 0.0)
    mux.publish("manual", MANUAL, 0.2)
    mux.publish("joy", JOY, 0.3)
    assert mux.active_source(0.6) == "joy"     # joy age 0.3
    assert mux.active_source(0.65) == "manual"  # joy dead, manual age 0.45
    assert mux.active_source(0.71) == IDLE      # manual age 0.51, auto age 0.71


def test_zero_twist_from_a_live_source_still_holds_the_bus(mux):
    mux.publish("auto", AUTO, 0.0)
    mux.publish("manual", ZERO_TWIST, 0.1)  # operator holding 'stop' overrides autonomy
    assert mux.select(0.2) == (ZERO_TWIST, "manual")


def test_unknown_source_rejected(mux):
    with pytest.raises(ValueError, match="unknown twist_mux source 'nav'"):
        mux.publish("nav", AUTO, 0.0)


def test_idle_is_reserved():
    cfg = MuxConfig(sources={"idle": MuxSource(priority=5, timeout=1.0)})
    with pytest.raises(ValueError):
        TwistMux(cfg)


def test_source_at_or_below_guard_priority_never_wins():
    cfg = MuxConfig(sources={"low": MuxSource(priority=1, timeout=1.0), "hi": MuxSource(priority=2, timeout=1.0)})
    mux = TwistMux(cfg)
    mux.publish("low", AUTO, 0.0)
    assert mux.active_source(0.5) == IDLE
    mux.publish("hi", JOY, 0.0)
    assert mux.active_source(0.5) == "hi"


def test_equal_priorities_resolve_by_config_order():
    cfg = MuxConfig(sources={"b": MuxSource(priority=5, timeout=1.0), "a": MuxSource(priority=5, timeout=1.0)})
    mux = TwistMux(cfg)
    mux.publish("a", AUTO, 0.0)
    mux.publish("b", JOY, 0.0)
    assert mux.active_source(0.1) == "b"


def test_non_finite_twists_are_dropped_and_the_source_times_out():
    mux = TwistMux(MuxConfig())
    mux.publish("manual", Twist(vx=0.2), 0.0)
    mux.publish("manual", Twist(vx=float("nan")), 0.3)
    mux.publish("joy", Twist(wz=float("inf")), 0.3)
    assert mux.select(0.4) == (Twist(vx=0.2), "manual")  # the last good command, still live
    assert mux.select(0.6) == (ZERO_TWIST, "idle")  # bad messages never refreshed it


def test_last_says_what_a_source_sent_and_when_live_or_not():
    from hw.config import MuxConfig
    from hw.interfaces import Twist
    from hw.twist_mux import TwistMux

    mux = TwistMux(MuxConfig())
    assert mux.last("manual") is None
    mux.publish("manual", Twist(0.1, 0.2, 0.3), 4.1)
    assert mux.last("manual") == (4.1, Twist(0.1, 0.2, 0.3))
    assert not mux.is_live("manual", 10.0) and mux.last("manual")[1].vy == 0.2
