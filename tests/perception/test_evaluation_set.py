"""The fixed-seed evaluation set: 16 randomized pots from the harness of ``lupin bench
perception`` (lighting jitter, approach noise inside the goal tolerance), scored against the
sim's truth. The benchmark runs the full set; this keeps a small one in every test run."""
from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from lupin.bench.perception import evaluate, render_shots  # noqa: E402
from mission.runtime.config import LupinConfig  # noqa: E402

SEED, SHOTS = 1, 16

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def evaluation():
    return evaluate(LupinConfig(), SHOTS, SEED)


def test_flower_figures(evaluation):
    f = evaluation.flower
    assert f["frames"] == SHOTS and f["scored"] >= SHOTS - 2
    assert f["accuracy"] >= 0.97
    assert f["bug_frames"] >= 2 and f["bug_recall"] == 1.0
    assert f["false_bug_rate"] == 0.0
    confusion = f["confusion"]
    assert {c for c in ("red", "white", "pink") if sum(confusion[c].values())} == {"red", "white", "pink"}


def test_tag_figures(evaluation):
    t = evaluation.tag
    assert t["scored"] >= 5 and t["accuracy"] == 1.0
    assert t["near_misreads"] == 0  # tags out of view are not replaced by a wrong near read
    assert t["position_error_m"][2] < 0.02 and t["rotation_error_deg"][2] < 3.0


def test_the_set_is_the_same_for_the_same_seed():
    a = list(render_shots(LupinConfig(), 2, SEED))
    b = list(render_shots(LupinConfig(), 2, SEED))
    for x, y in zip(a, b):
        assert x.noise == y.noise and x.lighting == y.lighting and x.pot_id == y.pot_id
        assert np.array_equal(x.wrist, y.wrist) and np.array_equal(x.front, y.front)
    assert a[0].noise != a[1].noise
