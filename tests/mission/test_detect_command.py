"""`lupin detect flower|tag IMAGE... [--json] [--annotate DIR]` (spec/cli.md): output per image,
unreadable files as one line each while the rest are still processed, exit codes, annotation."""
from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

from lupin.cli import main
from perception.config import TagConfig
from sim.apriltag import tag_image


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _bloom(path, colour_bgr, spot: bool) -> str:
    img = np.full((480, 640, 3), (40, 140, 40), np.uint8)
    cv2.circle(img, (300, 220), 80, colour_bgr, -1)
    if spot:
        cv2.circle(img, (310, 210), 15, (10, 10, 10), -1)
    cv2.imwrite(str(path), img)
    return str(path)


def _tag(path, tag_id: int, side_px: int = 200) -> str:
    """Tag ``tag_id`` head-on in the middle of a 640x480 frame, ``side_px`` across (black square)."""
    plate = cv2.cvtColor(tag_image(tag_id, pixels_per_module=side_px // 8, paper=(255, 255, 255), ink=(0, 0, 0)),
                         cv2.COLOR_RGB2BGR)
    frame = np.full((480, 640, 3), 90, np.uint8)
    y, x = (480 - plate.shape[0]) // 2, (640 - plate.shape[1]) // 2
    frame[y:y + plate.shape[0], x:x + plate.shape[1]] = plate
    cv2.imwrite(str(path), frame)
    return str(path)


def test_flower_json_and_unreadable_files(capsys, tmp_path):
    red = _bloom(tmp_path / "red.png", (40, 20, 220), spot=True)
    white = _bloom(tmp_path / "white.jpg", (245, 245, 245), spot=False)
    junk = tmp_path / "junk.png"
    junk.write_bytes(b"not a png")
    code, out, err = run(capsys, "detect", "flower", red, str(junk), str(tmp_path / "missing.png"), white, "--json")
    assert code == 2
    rows = [json.loads(line) for line in out.splitlines()]
    assert [r["image"] for r in rows] == [red, white]  # the good files after the bad one still ran
    assert (rows[0]["class"], rows[0]["count"], rows[0]["bug"]) == ("red", 1, True)
    assert (rows[1]["class"], rows[1]["bug"]) == ("white", False)
    det = rows[0]["detections"][0]
    assert set(det) == {"class", "centroid", "area", "confidence", "bug"}
    assert det["centroid"] == pytest.approx([300, 220], abs=2) and det["area"] == pytest.approx(np.pi * 80**2, rel=0.05)
    lines = err.strip().splitlines()
    assert len(lines) == 2 and "junk.png" in lines[0] and "missing.png: no such file" in lines[1]
    assert "Traceback" not in err


def test_flower_text_output(capsys, tmp_path):
    code, out, err = run(capsys, "detect", "flower", _bloom(tmp_path / "p.png", (200, 150, 255), spot=False))
    assert code == 0 and err == ""
    assert out.splitlines()[0].endswith("p.png: pink x1") and "confidence" in out


def test_a_pest_on_a_leaf_in_text_and_json(capsys, tmp_path):
    img = np.full((480, 640, 3), 110, np.uint8)
    cv2.circle(img, (300, 220), 100, (40, 140, 40), -1)  # a plant with no bloom
    cv2.circle(img, (280, 200), 15, (10, 10, 10), -1)  # a pest on its leaves
    path = str(tmp_path / "leaf.png")
    cv2.imwrite(path, img)
    code, out, _ = run(capsys, "detect", "flower", path)
    assert code == 0 and out.splitlines()[0].endswith("leaf.png: none, BUG") and "pest on a leaf at (280, 200)" in out
    code, out, _ = run(capsys, "detect", "flower", path, "--json")
    (row,) = [json.loads(line) for line in out.splitlines()]
    assert (row["class"], row["bug"], row["detections"]) == ("none", True, [])
    (pest,) = row["pests"]
    assert pest["on"] == "leaf" and pest["centroid"] == pytest.approx([280, 200], abs=2) and pest["confidence"] > 0.8


def test_tag_json_pose(capsys, tmp_path):
    img = _tag(tmp_path / "t.png", 5)
    code, out, _ = run(capsys, "detect", "tag", img, "--json")
    assert code == 0
    (row,) = [json.loads(line) for line in out.splitlines()]
    (det,) = row["detections"]
    f = TagConfig().camera.matrix()[0, 0]
    assert det["id"] == 5
    assert det["pose"]["position"][2] == pytest.approx(f * 0.10 / 200, rel=0.02)  # pinhole: z = f * size / px
    assert det["off_axis"] < 0.05 and set(det) >= {"id", "pose", "off_axis"}


def test_tag_text_and_non_whitelisted(capsys, tmp_path):
    code, out, _ = run(capsys, "detect", "tag", _tag(tmp_path / "a.png", 3), _tag(tmp_path / "b.png", 300))
    assert code == 0
    first, *rest = out.splitlines()
    assert first.endswith("a.png: tag 3") and "off-axis" in rest[0]
    assert out.splitlines()[-1].endswith("b.png: no tag")


def test_annotate_writes_each_image(capsys, tmp_path):
    out_dir = tmp_path / "ann"
    out_dir.mkdir()
    src = _bloom(tmp_path / "x.png", (40, 20, 220), spot=True)
    code, _, _ = run(capsys, "detect", "flower", src, "--annotate", str(out_dir))
    assert code == 0
    (written,) = list(out_dir.iterdir())
    drawn, original = cv2.imread(str(written)), cv2.imread(src)
    assert drawn.shape == original.shape and np.count_nonzero(np.any(drawn != original, axis=2)) > 500
    code, _, _ = run(capsys, "detect", "tag", _tag(tmp_path / "t.png", 2), "--annotate", str(out_dir))
    assert code == 0 and len(list(out_dir.iterdir())) == 2


@pytest.mark.parametrize("argv,needle", [
    (["detect", "leaf", "x.png"], "unknown detector 'leaf'"),
    (["detect", "flower", "x.png", "--annotate", "/nonexistent/dir"], "not a directory"),
])
def test_bad_options_are_one_line_exit_2(capsys, argv, needle):
    code, out, err = run(capsys, *argv)
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1 and out == ""


def test_help(capsys):
    code, out, _ = run(capsys, "detect", "--help")
    assert code == 0 and "--annotate" in out and "--json" in out
