"""Scoring: confusion matrix, precision / recall, pest rates, tag accuracy and pose error."""
from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from perception.evaluation import rotation_error, score_flowers, score_tags


def test_flower_scores_by_hand():
    truth = ["red", "red", "white", "pink", "none", "none", None]
    pred = ["red", "pink", "white", "pink", "none", "white", "red"]
    bug_truth = [True, False, False, True, False, None, True]
    bug_pred = [True, True, False, False, False, True, True]
    s = score_flowers(truth, pred, bug_truth, bug_pred, [1, 2, 1, 1, 0, 0, None], [1, 1, 1, 1, 0, 1, 1])
    assert s.frames == 6                      # the marginal frame (None) is not scored
    assert s.accuracy == pytest.approx(4 / 6)
    assert s.confusion["red"] == {"red": 1, "white": 0, "pink": 1, "none": 0}
    assert s.confusion["none"]["white"] == 1
    assert s.precision["pink"] == pytest.approx(1 / 2) and s.recall["pink"] == 1.0
    assert s.precision["white"] == pytest.approx(1 / 2) and s.recall["red"] == pytest.approx(1 / 2)
    assert s.bug_recall == pytest.approx(2 / 3)   # frames 0, 3, 6 carry a visible pest
    assert s.false_bug_rate == pytest.approx(1 / 3)  # frames 1, 2, 4 are clean; 1 was flagged
    assert s.bug_frames == 3
    assert s.count_accuracy == pytest.approx(3 / 4)  # frames with blooms and a known count


def test_undefined_ratios_are_none():
    s = score_flowers(["none"], ["none"], [False], [False])
    assert s.bug_recall is None and s.precision["red"] is None and s.count_accuracy is None
    assert s.false_bug_rate == 0.0 and s.accuracy == 1.0


def test_rotation_error():
    r = cv2.Rodrigues(np.array([0.1, -0.2, 0.3]))[0]
    turned = r @ cv2.Rodrigues(np.array([0.0, 0.0, math.radians(5)]))[0]
    assert rotation_error(cv2.Rodrigues(r)[0].ravel(), r) == pytest.approx(0.0, abs=1e-7)
    assert rotation_error(cv2.Rodrigues(r)[0].ravel(), turned) == pytest.approx(math.radians(5), abs=1e-7)


def test_tag_scores():
    s = score_tags([1, 2, 3, 4], [1, 2, 9, None], [0.001, 0.003, 0.5, None], [0.0, math.radians(2), 1.0, None])
    assert s.frames == 4 and s.accuracy == 0.5
    assert s.position_error_m[2] == pytest.approx(0.003)   # wrong ids do not count towards pose error
    assert s.rotation_error_deg[2] == pytest.approx(2.0)
    empty = score_tags([], [], [], [])
    assert empty.accuracy == 0.0 and math.isnan(empty.position_error_m[0])
