"""Loop closure in a repetitive row: a match that cannot tell one pot from the next is refused,
a match with something to tell it by (an end wall in reach) is taken."""
from __future__ import annotations

import numpy as np
import pytest

from hw.odometry import Pose2D
from nav.slam import loop_closure
from nav.slam.config import SlamConfig
from nav.slam.loop_closure import LoopCloser
from nav.slam.scan_points import scan_points
from tests.nav.builders import RES, greenhouse_occupancy, scan_from_occupancy

# A 40 m hall, two rows of pots every metre either side of the aisle at y = 2: from its middle
# the end walls are 20 m away, beyond the lidar's 12 m.
HALL = greenhouse_occupancy(floor=(40.0, 4.0), rows=(1.0, 3.0), pots_x=tuple(np.arange(1.0, 39.5, 1.0)))


def keyframe_scan(x: float) -> np.ndarray:
    scan = scan_from_occupancy(HALL, RES, (x, 2.0, 0.0), beams=720)
    return scan_points(scan.angles, scan.ranges, Pose2D(), 0.25, 12.0)


def attempt(true_x: float, believed_x: float):
    """Old keyframes every 0.25 m round ``true_x`` at their true poses; the new keyframe's scan
    is taken at ``true_x`` but the graph believes it is at ``believed_x``."""
    xs = list(np.arange(true_x - 1.5, true_x + 1.5 + 1e-9, 0.25))
    poses = np.array([[x, 2.0, 0.0] for x in xs] + [[believed_x, 2.0, 0.0]])
    scans = [keyframe_scan(x) for x in xs] + [keyframe_scan(true_x)]
    candidate = int(np.argmin(np.abs(np.array(xs) - believed_x)))
    return LoopCloser(SlamConfig()).match(poses, scans, candidate, len(xs))


def test_mid_row_a_match_one_pot_along_is_refused(monkeypatch):
    """Drifted 0.8 m, mid-row: the scan fits the row one pot along, 0.2 m from where the graph
    believes it is: without the uniqueness test that is a small correction (under the 0.5 m
    cap) onto the wrong pot, a metre off; with it, refused, as is any mid-row match however
    small."""
    monkeypatch.setattr(loop_closure, "UNIQUE_LEAD", -1.0)  # without the uniqueness test ...
    wrong = attempt(20.0, 20.8)
    assert wrong is not None and wrong.correction < 0.5  # ... accepted
    assert 20.75 + wrong.relative.x == pytest.approx(21.0, abs=0.05)  # placed one pot off the truth
    monkeypatch.undo()
    assert attempt(20.0, 20.8) is None  # refused: it cannot tell which pot it is at
    assert attempt(20.0, 20.1) is None  # however near the estimate, mid-row it stays ambiguous


def test_with_the_end_wall_in_reach_the_match_is_taken_and_corrects_the_drift():
    match = attempt(4.0, 4.15)  # the candidate is the old keyframe at 4.25
    assert match is not None and match.correction == pytest.approx(0.15, abs=0.03)
    assert 4.25 + match.relative.x == pytest.approx(4.0, abs=0.03)
