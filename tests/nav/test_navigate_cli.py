"""`lupin sim navigate`: outcome JSON, the picture, and bad goals as bad input (exit 2)."""
from __future__ import annotations

import json

import cv2
import pytest

from lupin.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.slow
def test_navigate_json_and_picture(capsys, tmp_path):
    pic = tmp_path / "nav.png"
    code, out, err = run(capsys, "sim", "navigate", "--to", "2.5,0.5,0.0", "--json", "--picture", str(pic))
    assert code == 0, err
    result = json.loads(out)
    assert set(result) == {"outcome", "reason", "sim_time_s", "wall_time_s", "distance_m", "truth_error"}
    assert result["outcome"] == "succeeded" and result["reason"] == ""
    assert 1.2 < result["distance_m"] < 2.5
    assert result["truth_error"]["xy"] < 0.25 and result["truth_error"]["yaw"] < 0.12
    img = cv2.imread(str(pic))
    assert img is not None and img.shape[0] > 50 and img.shape[1] > 100


@pytest.mark.parametrize("goal, words", [
    ("3.0,1.0,0", "overlaps pots[1] (id P02)"),   # inside a pot
    ("9.0,1.0,0", "crosses the east wall"),         # off the floor
    ("6.6,3.6,0", "overlaps obstacles[0]"),         # inside the crate
])
def test_goal_inside_an_obstacle_or_off_the_floor_is_bad_input(capsys, goal, words):
    code, out, err = run(capsys, "sim", "navigate", "--to", goal)
    assert code == 2 and out == ""
    assert "bad goal" in err and words in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("argv, words", [
    (["--to", "1,2"], "expected X,Y,YAW"),
    (["--to", "1,2,nan"], "finite"),
    (["--to", "2,0.5,0", "--timeout", "-3"], "--timeout"),
    (["--to", "2,0.5,0", "--picture", "x.jpg"], "must be a .png"),
])
def test_bad_options_are_one_line_exit_2(capsys, argv, words):
    code, out, err = run(capsys, "sim", "navigate", *argv)
    assert code == 2 and words in err and "Traceback" not in err
