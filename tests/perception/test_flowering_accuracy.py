"""``flowering_accuracy`` scores only the frames with a bloom in view, so easy ``none`` frames
cannot lift it; marginal (None) frames stay out of both figures."""
from perception.evaluation import score_flowers


def test_easy_negatives_lift_accuracy_but_not_flowering_accuracy():
    truth = ["none"] * 8 + ["red", "pink", None, "white"]
    pred = ["none"] * 8 + ["red", "none", "red", "pink"]
    s = score_flowers(truth, pred, [False] * 12, [False] * 12)
    assert s.frames == 11 and abs(s.accuracy - 9 / 11) < 1e-9
    assert s.flowering_frames == 3 and abs(s.flowering_accuracy - 1 / 3) < 1e-9


def test_no_bloom_in_view_has_no_flowering_figure():
    s = score_flowers(["none", "none"], ["none", "red"], [False, False], [False, False])
    assert s.flowering_accuracy is None and s.flowering_frames == 0 and s.accuracy == 0.5
