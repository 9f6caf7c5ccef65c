"""``arm.ik`` asks for the impossible and the edge too: unreachable targets are refused with a
reason, a claimed success that misses is counted as a wrong answer, and borderline targets get
the answer their side of the edge calls for."""
from __future__ import annotations

import numpy as np
import pytest

from arm.aim import AimResult, CameraAim, bloom_can_be_at, sample_reachable_targets
from arm.config import ArmConfig
from arm.presets import PRESETS
from lupin.bench.arm import judge, tally
from lupin.bench.ik_targets import (EXPECTED, beyond_reach, below_floor, borderline, inside_body,
                                    outside_joint_limits)

CONFIG = ArmConfig()
K, C = CONFIG.kinematics, CONFIG.ik


@pytest.fixture(scope="module")
def aim():
    return CameraAim(K, C)


@pytest.mark.parametrize("make, words", [
    (beyond_reach, "beyond reach"),
    (below_floor, "below the floor"),
    (inside_body, "inside the robot's body"),
    (outside_joint_limits, "shoulder_pan window"),
])
def test_unreachable_targets_are_refused_with_their_reason(aim, make, words):
    for t in make(6, 11, K, C):
        r = aim.aim(t)
        assert not r.ok and r.q is None and words in r.reason, (t, r.reason)
        assert judge(t, r, K, C) == "refused"


def test_a_claimed_success_that_misses_is_a_wrong_answer():
    target = np.array([0.35, 0.0, 0.1])
    liar = AimResult(True, np.array(PRESETS["zero"], dtype=float), miss=0.0, range=0.2)  # looks straight up
    assert judge(target, liar, K, C) == "wrong"
    out_of_windows = AimResult(True, np.array([2.0, 0.0, 0.0, 0.0]))
    assert judge(target, out_of_windows, K, C) == "wrong"
    summary = tally({"reachable": ["solved", "wrong", "refused"], "below_floor": ["refused", "wrong"]},
                    {"reachable": [1.0, 2.0, 3.0], "below_floor": [0.1, 0.2]}, {})
    assert summary["wrong_answers"] == 2
    assert summary["failures"] == 3  # two wrong, one reachable target refused
    assert summary["classes"]["reachable"]["as_expected"] == 1 and summary["classes"]["below_floor"]["as_expected"] == 1


def test_a_success_aimed_below_the_floor_is_wrong_even_on_its_axis(aim):
    t = np.array([0.35, 0.0, -0.2])
    q = np.array(PRESETS["inspect"], dtype=float)
    assert judge(t, AimResult(True, q), K, C) == "wrong"


def test_reachable_targets_are_where_a_bloom_can_be():
    for t in sample_reachable_targets(60, 2, K, C):
        assert bloom_can_be_at(t, C)


def test_borderline_targets_are_answered_by_their_side_of_the_edge(aim):
    inside, outside = borderline(6, 5, K, C)
    assert [judge(t, aim.aim(t), K, C) for t in inside] == ["solved"] * 6
    assert [judge(t, aim.aim(t), K, C) for t in outside] == ["refused"] * 6
    assert EXPECTED["just_inside"] == "solved" and EXPECTED["just_outside"] == "refused"
