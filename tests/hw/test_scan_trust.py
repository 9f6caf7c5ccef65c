"""The blind rule (hw/scan_trust.py) on synthetic scans: all-invalid, the front arc covered and a
sudden collapse are blind; an honest view out of an open aisle end, turned into over many
revolutions, is not; a blind scan never becomes the baseline."""
from __future__ import annotations

import math

import numpy as np

from hw.config import BlindRule
from hw.scan_trust import ScanTrust

ANGLES = (np.arange(500) * (2 * math.pi / 500)).astype(np.float32)  # the C1's ~500 beams


def wrap(a):
    return np.angle(np.exp(1j * np.asarray(a, dtype=float)))


def honest(trust: ScanTrust, n: int = 10) -> None:
    for _ in range(n):
        assert trust.judge(ANGLES, np.ones(500, dtype=bool)) is None


def test_no_valid_return_is_blind_even_without_history():
    assert ScanTrust(BlindRule()).judge(ANGLES, np.zeros(500, dtype=bool)) is not None


def test_the_front_arc_covered_is_blind():
    trust = ScanTrust(BlindRule())
    honest(trust)
    covered = np.abs(wrap(ANGLES)) > math.radians(50)  # a hand over the front 100 deg
    assert "front arc" in trust.judge(ANGLES, covered)


def test_a_sudden_collapse_is_blind():
    trust = ScanTrust(BlindRule())
    honest(trust)
    sun = np.arange(500) % 5 < 2  # 40 % of the returns left, everywhere (sun glare)
    assert "fell" in trust.judge(ANGLES, sun)


def test_turning_to_face_an_open_aisle_end_is_not_blind():
    """An open end 100 deg wide where nothing is within 12 m: the robot turns to face it at
    1 rad/s (6 deg per revolution), then stands facing out; the front arc empties gradually."""
    trust = ScanTrust(BlindRule())
    for k in range(40):
        heading = min(k * 0.1, math.pi)  # the open end is behind at first, ahead at the end
        bearing = wrap(ANGLES - (math.pi - heading))
        valid = np.abs(bearing) > math.radians(50)
        assert trust.judge(ANGLES, valid) is None, k
    assert trust.shares[1] < 0.2  # it does face the open end: the front arc is mostly empty


def test_a_blind_scan_does_not_become_the_baseline():
    trust = ScanTrust(BlindRule(history=3))
    honest(trust, 3)
    half = np.arange(500) % 10 < 3
    for _ in range(5):  # stays blind however long it lasts
        assert trust.judge(ANGLES, half) is not None
    assert trust.judge(ANGLES, np.ones(500, dtype=bool)) is None
