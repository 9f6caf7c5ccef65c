"""Blind is not clear: whether a scan that arrived on time can be trusted to show what is there.

A covered or sun-blinded RPLidar still delivers its revolutions on time, every return invalid
(the C1 reports 0, which arrives as ``inf``); so does one whose returns all fall under
``range_min``. Counted as points, such a scan holds nothing, and a monitor that only asks "is
there a point in the zone?" calls it clear and lets the base drive at full speed (issue 28
item 3). A scan is judged on its share of valid returns, over all beams and over the arc ahead
(``BlindRule``: a low floor, and a sudden fall, relative and absolute, against the median of
the last trusted scans, so an honest view down an open aisle end is not blind). Blind scans never join that median.
"""
from __future__ import annotations

import math
from collections import deque

import numpy as np

from hw.config import BlindRule


class ScanTrust:
    def __init__(self, rule: BlindRule):
        self.rule = rule
        self._recent: deque[tuple[float, float]] = deque(maxlen=rule.history)
        self.shares = (math.nan, math.nan)
        """The last scan's valid shares: all beams, the front arc."""

    def judge(self, angles: np.ndarray, valid: np.ndarray) -> str | None:
        """Why the scan (its beam angles in the lidar frame and which returns are valid) is
        blind, or None when it can be trusted (it then joins the baseline)."""
        r = self.rule
        whole = float(np.mean(valid)) if len(valid) else 0.0
        ahead = np.abs(np.angle(np.exp(1j * np.asarray(angles, dtype=np.float64)))) <= r.front_arc / 2
        front = float(np.mean(valid[ahead])) if ahead.any() else whole
        self.shares = (whole, front)
        why = None
        if whole < r.min_valid:
            why = f"{whole:.0%} of the returns valid (< {r.min_valid:.0%})"
        elif self._recent:
            base_whole, base_front = np.median(np.asarray(self._recent), axis=0)
            if _fell(whole, base_whole, r):
                why = f"valid returns fell to {whole:.0%} from {base_whole:.0%}"
            elif _fell(front, base_front, r):
                why = f"the front arc's valid returns fell to {front:.0%} from {base_front:.0%}"
        if why is None:
            self._recent.append((whole, front))
        return why


def _fell(share: float, base: float, r: BlindRule) -> bool:
    return share < r.collapse * base and base - share >= r.min_drop
