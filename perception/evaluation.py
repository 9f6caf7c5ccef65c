"""Scoring detectors against ground truth: confusion matrix, precision / recall, pest rates
(overall, and on blooms and on leaves apart), tag-id accuracy and pose error. Pure functions over plain lists, so the sim harness
(lupin/bench/perception.py), the tests and a future real-photo set all score alike.

Truth for a frame is what the camera could see, not what the pot holds: a bloom pushed out of
the wrist frame by approach-pose noise is truthfully ``none`` for the detector (the harness
reports separately how often that happened). Frames whose truth is marginal (a bloom or pest
only a sliver of which is in view) carry ``None`` and are left out of the score.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import cv2
import numpy as np

FLOWER_CLASSES = ("red", "white", "pink", "none")


@dataclass(frozen=True)
class FlowerScore:
    frames: int
    """Frames scored for class (marginal truth excluded)."""
    accuracy: float
    confusion: dict[str, dict[str, int]]
    """truth class -> predicted class -> frames."""
    precision: dict[str, Optional[float]]
    recall: dict[str, Optional[float]]
    count_accuracy: Optional[float]
    """Among frames with visible blooms of a known count, how often the count was right."""
    bug_recall: Optional[float]
    false_bug_rate: Optional[float]
    bug_frames: int
    """Frames with a visible pest (the bug recall's denominator)."""
    flowering_accuracy: Optional[float] = None
    """Accuracy on the frames whose truth is a bloom in view (any class but ``none``): the
    figure the easy negatives cannot lift."""
    flowering_frames: int = 0
    """Frames with a bloom in view (its denominator)."""


def _ratio(num: int, den: int) -> Optional[float]:
    return None if den == 0 else num / den


def score_flowers(truth: Sequence[Optional[str]], predicted: Sequence[str],
                  bug_truth: Sequence[Optional[bool]], bug_predicted: Sequence[bool],
                  count_truth: Sequence[Optional[int]] = (), count_predicted: Sequence[int] = (),
                  classes: Sequence[str] = FLOWER_CLASSES) -> FlowerScore:
    """Score per-frame predictions; ``None`` truths are skipped for that figure."""
    confusion = {t: {p: 0 for p in classes} for t in classes}
    for t, p in zip(truth, predicted):
        if t is not None:
            confusion[t][p] += 1
    n = sum(sum(row.values()) for row in confusion.values())
    correct = sum(confusion[c][c] for c in classes)
    flowering = [c for c in classes if c != "none"]
    n_flowering = sum(sum(confusion[c].values()) for c in flowering)
    precision = {c: _ratio(confusion[c][c], sum(confusion[t][c] for t in classes)) for c in classes}
    recall = {c: _ratio(confusion[c][c], sum(confusion[c].values())) for c in classes}
    counted = [(t, p) for t, p, cls in zip(count_truth, count_predicted, truth) if t and cls not in (None, "none")]
    bugs = [p for t, p in zip(bug_truth, bug_predicted) if t is True]
    clean = [p for t, p in zip(bug_truth, bug_predicted) if t is False]
    return FlowerScore(
        frames=n, accuracy=_ratio(correct, n) or 0.0, confusion=confusion, precision=precision, recall=recall,
        count_accuracy=_ratio(sum(t == p for t, p in counted), len(counted)),
        bug_recall=_ratio(sum(bugs), len(bugs)), false_bug_rate=_ratio(sum(clean), len(clean)),
        bug_frames=len(bugs),
        flowering_accuracy=_ratio(sum(confusion[c][c] for c in flowering), n_flowering), flowering_frames=n_flowering)


PEST_SITES = ("bloom", "leaf")


@dataclass(frozen=True)
class PestScore:
    """Pests judged per site (issue 30: a pest on a leaf is as much a pest as one on a bloom)."""

    recall: dict[str, Optional[float]]
    """Site -> share of the frames with a visible pest there in which a pest was reported."""
    frames: dict[str, int]
    """Site -> frames with a visible pest there (the recall's denominator)."""
    false_rate: Optional[float]
    """Share of the frames with no pest in view in which one was reported (any site)."""
    false_on: dict[str, Optional[float]]
    """Site -> share of those frames in which a pest was reported on that site."""
    clean_frames: int
    """Frames with no pest in view (the false rates' denominator)."""


def score_pests(truth: Sequence[Optional[bool]], truth_on: Sequence[Optional[str]],
                predicted_on: Sequence[Sequence[str]], sites: Sequence[str] = PEST_SITES) -> PestScore:
    """``truth[i]``: a pest in view (None: marginal, skipped); ``truth_on[i]``: the site of the
    frame's pest; ``predicted_on[i]``: the sites of the pests the detector reported."""
    found = {s: [bool(p) for t, o, p in zip(truth, truth_on, predicted_on) if t is True and o == s] for s in sites}
    clean = [set(p) for t, p in zip(truth, predicted_on) if t is False]
    return PestScore(
        recall={s: _ratio(sum(v), len(v)) for s, v in found.items()}, frames={s: len(v) for s, v in found.items()},
        false_rate=_ratio(sum(bool(p) for p in clean), len(clean)),
        false_on={s: _ratio(sum(s in p for p in clean), len(clean)) for s in sites}, clean_frames=len(clean))


def rotation_error(rvec: Sequence[float], r_true: np.ndarray) -> float:
    """Angle of the rotation between a Rodrigues vector and a true rotation matrix, rad."""
    r = cv2.Rodrigues(np.asarray(rvec, np.float64))[0]
    cos = (np.trace(r.T @ np.asarray(r_true, np.float64)) - 1.0) / 2.0
    return math.acos(max(-1.0, min(1.0, float(cos))))


@dataclass(frozen=True)
class TagScore:
    frames: int
    """Frames with the expected tag fully in view."""
    accuracy: float
    """Share of those whose nearest read carries the expected id."""
    position_error_m: tuple[float, float, float]
    """Median, p95 and max of the position error of correct reads, m."""
    rotation_error_deg: tuple[float, float, float]
    """Median, p95 and max of the rotation error of correct reads, deg."""


def _stats(values: Sequence[float]) -> tuple[float, float, float]:
    if not values:
        return (math.nan, math.nan, math.nan)
    v = np.asarray(values, dtype=float)
    return float(np.median(v)), float(np.percentile(v, 95)), float(v.max())


def score_tags(expected: Sequence[int], read_ids: Sequence[Optional[int]],
               position_errors: Sequence[Optional[float]], rotation_errors: Sequence[Optional[float]]) -> TagScore:
    """``read_ids[i]``: id of the nearest read in frame i (None: nothing read); errors are
    those of that read against the truth (None when nothing was read)."""
    ok = [i for i, (e, r) in enumerate(zip(expected, read_ids)) if r == e]
    return TagScore(
        frames=len(expected), accuracy=_ratio(len(ok), len(expected)) or 0.0,
        position_error_m=_stats([position_errors[i] for i in ok]),
        rotation_error_deg=_stats([math.degrees(rotation_errors[i]) for i in ok]))
