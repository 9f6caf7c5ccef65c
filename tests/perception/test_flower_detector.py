"""The HSV flower detector on frames the sim renders at the patrol's inspect view, on JPEG copies and resized
copies of them, on drawn frames for the pest rule, and on garbage."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from perception.config import FlowerConfig, HsvRange
from perception.flower_detector import FlowerDetector, _lookup_tables
from tests.perception.conftest import LEAF, POTS

DETECT = FlowerDetector()


@pytest.mark.slow
@pytest.mark.parametrize("pot_id", ["P01", "P02", "P03"])
def test_each_class_from_the_approach_pose(scenes, pot_id):
    flower = POTS[pot_id][0]
    frame = DETECT(scenes[pot_id].wrist)
    assert scenes[pot_id].flower_truth == flower  # the bloom is in view
    assert frame.flower == flower
    assert frame.count == 1
    assert {b.cls for b in frame.blooms} == {flower}
    assert not frame.bug
    assert frame.confidence > 0.9


@pytest.mark.slow
def test_a_pot_without_a_plant_has_no_bloom(scenes):
    frame = DETECT(scenes["P04"].wrist)
    assert frame.flower == "none" and frame.count == 0 and frame.blooms == () and not frame.bug
    assert frame.confidence == 0.0


@pytest.mark.slow
def test_two_blooms_of_the_same_colour_count_two(scenes):
    scene = scenes["P05"]
    frame = DETECT(scene.wrist)
    assert scene.count_truth == 2
    assert (frame.flower, frame.count) == ("red", 2)
    a, b = (bl.centroid for bl in frame.blooms)
    assert abs(a[0] - b[0]) > 100  # two separate blobs, side by side in the frame


@pytest.mark.slow
def test_three_white_blooms(scenes):
    scene = scenes["P07"]
    frame = DETECT(scene.wrist)
    assert frame.flower == "white" and frame.count == scene.count_truth


@pytest.mark.slow
@pytest.mark.parametrize("pot_id", ["P06", "P08"])
def test_a_pest_on_a_bloom_is_reported_on_that_bloom(scenes, pot_id):
    scene = scenes[pot_id]
    frame = DETECT(scene.wrist)
    assert scene.bug_truth is True
    assert frame.flower == POTS[pot_id][0]
    assert frame.bug
    assert sum(b.bug for b in frame.blooms) == 1  # only the bloom carrying it


@pytest.mark.slow
@pytest.mark.parametrize("pot_id", list(LEAF))
def test_a_pest_on_a_leaf_is_found_at_the_inspect_view(leaf_scenes, pot_id):
    """Issue 30: a pest on a leaf, of a plant with no bloom or of a flowering one, is a pest."""
    scene = leaf_scenes[pot_id]
    flower, blooms = LEAF[pot_id][:2]
    frame = DETECT(scene.wrist)
    assert scene.bug_truth is True  # the pest is in view
    assert frame.bug and [p.on for p in frame.pests] == ["leaf"] and frame.pest.confidence > 0.8
    assert not any(b.bug for b in frame.blooms)  # on no bloom
    assert (frame.flower, frame.count) == (flower, 0 if flower == "none" else blooms)


@pytest.mark.slow
@pytest.mark.parametrize("pot_id", ["P01", "P02", "P03", "P05", "P07"])
def test_no_pest_on_clean_blooms(scenes, pot_id):
    assert not DETECT(scenes[pot_id].wrist).bug


@pytest.mark.slow
@pytest.mark.parametrize("brightness,tint,tilt", [
    (0.65, (1.08, 1.0, 0.92), (0.5, -0.5)),   # dim, warm, low sun
    (1.35, (0.92, 1.0, 1.08), (-0.5, 0.5)),   # bright, cool
])
def test_lighting_extremes(studio, brightness, tint, tilt):
    for pot_id in ("P03", "P06", "P02", "P04"):
        scene = studio.shoot(pot_id, lighting=(brightness, tint, tilt))
        frame = DETECT(scene.wrist)
        assert frame.flower == scene.flower_truth, pot_id
        assert frame.bug == scene.bug_truth, pot_id


@pytest.mark.slow
def test_jpeg_copies_read_the_same(scenes):
    """Frames leave the robot as JPEG and come back through ``lupin detect``."""
    for pot_id in ("P02", "P05", "P06"):
        raw = DETECT(scenes[pot_id].wrist)
        ok, buf = cv2.imencode(".jpg", scenes[pot_id].wrist, [cv2.IMWRITE_JPEG_QUALITY, 80])
        jpeg = DETECT(cv2.imdecode(buf, cv2.IMREAD_COLOR))
        assert (jpeg.flower, jpeg.count, jpeg.bug) == (raw.flower, raw.count, raw.bug)


@pytest.mark.slow
def test_a_big_photo_reports_in_its_own_pixels(scenes):
    small = DETECT(scenes["P05"].wrist)
    big = DETECT(cv2.resize(scenes["P05"].wrist, (2560, 1920), interpolation=cv2.INTER_CUBIC))
    assert (big.flower, big.count) == (small.flower, small.count)
    for s, b in zip(small.blooms, big.blooms):
        assert b.centroid == pytest.approx((s.centroid[0] * 4 + 1.5, s.centroid[1] * 4 + 1.5), abs=6)
        assert b.area == pytest.approx(16 * s.area, rel=0.05)


def _drawn(spot_at: tuple[int, int] | None, field=(40, 140, 40)) -> np.ndarray:
    """A field (leaf green unless asked) with one red disc (BGR), and a dark spot where asked."""
    img = np.full((480, 640, 3), field, np.uint8)
    cv2.circle(img, (320, 240), 70, (40, 20, 220), -1)
    if spot_at is not None:
        cv2.circle(img, spot_at, 14, (10, 10, 10), -1)
    return img


GREY = (110, 110, 110)
"""Floor or soil: neither bloom nor leaf."""


def test_a_dark_spot_inside_a_bloom_is_a_pest_on_it_one_in_the_leaves_a_pest_on_a_leaf():
    inside = DETECT(_drawn((330, 230)))
    beside = DETECT(_drawn((320, 240 + 70 + 25)))   # in the leaves, just below the bloom
    edge = DETECT(_drawn((320, 240 + 70)))          # half on the rim: half the ring is leaf
    assert inside.bug and inside.flower == "red" and inside.blooms[0].bug
    assert [p.on for p in inside.pests] == ["bloom"] and inside.pest.confidence > 0.8
    for frame in (beside, edge):
        assert frame.bug and frame.flower == "red" and not frame.blooms[0].bug  # not on the bloom
        assert [p.on for p in frame.pests] == ["leaf"] and frame.pest.confidence > 0.8
    assert beside.pest.centroid == pytest.approx((320, 335), abs=1.5)
    assert not DETECT(_drawn(None)).bug


def _on_soil(spot_at: tuple[int, int] | None) -> np.ndarray:
    """Floor or soil (grey), a ring of leaves and a red bloom in it, and a dark spot where asked."""
    img = np.full((480, 640, 3), GREY, np.uint8)
    cv2.circle(img, (320, 240), 85, (40, 140, 40), -1)
    cv2.circle(img, (320, 240), 70, (40, 20, 220), -1)
    if spot_at is not None:
        cv2.circle(img, spot_at, 14, (10, 10, 10), -1)
    return img


def test_a_dark_spot_on_the_floor_or_soil_is_no_pest():
    frame = DETECT(_on_soil((320, 240 + 70 + 45)))  # clear of the leaves
    assert frame.flower == "red" and not frame.bug and frame.pests == ()
    frame = DETECT(_on_soil((330, 230)))
    assert frame.bug and [p.on for p in frame.pests] == ["bloom"]  # on the bloom it still is one


def test_a_bloom_coloured_blob_with_no_leaf_around_it_is_no_bloom():
    """A pale wall behind the row or a plate's sunlit edge reads white; a bloom grows on a plant."""
    wall = np.full((480, 640, 3), GREY, np.uint8)
    cv2.rectangle(wall, (0, 0), (639, 60), (235, 240, 238), -1)  # the wall along the top
    cv2.circle(wall, (320, 260), 90, (40, 140, 40), -1)  # a plant with no bloom
    assert DETECT(wall).flower == "none" and DETECT(wall).blooms == ()
    cv2.circle(wall, (320, 260), 50, (235, 240, 238), -1)  # now it has a white bloom
    frame = DETECT(wall)
    assert (frame.flower, frame.count) == ("white", 1) and frame.blooms[0].centroid == pytest.approx((320, 260), abs=2)


def test_a_pest_on_a_plant_with_no_bloom():
    img = np.full((480, 640, 3), GREY, np.uint8)
    cv2.circle(img, (320, 240), 90, (40, 140, 40), -1)  # the leaves
    cv2.circle(img, (300, 220), 14, (10, 10, 10), -1)
    frame = DETECT(img)
    assert frame.flower == "none" and frame.blooms == () and frame.bug
    assert [p.on for p in frame.pests] == ["leaf"] and frame.pest.centroid == pytest.approx((300, 220), abs=1.5)
    assert frame.as_dict()["pests"][0]["on"] == "leaf"
    sliver = np.full((480, 640, 3), GREY, np.uint8)
    cv2.circle(sliver, (320, 240), 90, (40, 140, 40), -1)
    cv2.circle(sliver, (300, 220), 4, (10, 10, 10), -1)  # ~50 px: a pest, but a small one
    small = DETECT(sliver)
    assert small.bug and small.pest.confidence < 0.5 < frame.pest.confidence


def test_tiny_blobs_are_dropped():
    img = np.full((480, 640, 3), (40, 140, 40), np.uint8)
    cv2.circle(img, (100, 100), 5, (40, 20, 220), -1)      # ~80 px < 150 px
    cv2.circle(img, (400, 300), 12, (40, 20, 220), -1)     # ~450 px
    frame = DETECT(img)
    assert frame.count == 1 and frame.blooms[0].centroid == pytest.approx((400, 300), abs=1.5)


@pytest.mark.parametrize("garbage", [
    None, np.zeros((0, 0, 3), np.uint8), np.zeros((480, 640, 3), np.float32), np.zeros((480, 640, 5), np.uint8),
    np.zeros((2, 2, 3), np.uint8), "frame.png", np.zeros((480, 640, 3), np.uint8),
    np.random.default_rng(0).integers(0, 256, (480, 640), dtype=np.uint8),
])
def test_garbage_frames_give_no_bloom(garbage):
    frame = DETECT(garbage)
    assert frame.blooms == () and frame.flower == "none"


def test_lookup_tables_match_the_hsv_boxes():
    """The bit tables classify exactly like the plain per-class boxes, wrap-around included."""
    c = FlowerConfig()
    lut, label_lut, bug_lut, leaf_lut = _lookup_tables(list(c.classes.values()), c.bug, c.leaf)
    rng = np.random.default_rng(1)
    hsv = np.stack([rng.integers(0, 180, 20000), rng.integers(0, 256, 20000), rng.integers(0, 256, 20000)], 1)

    def inside(r: HsvRange, h, s, v):
        hue = (h >= r.h_lo) & (h <= r.h_hi) if r.h_lo <= r.h_hi else (h >= r.h_lo) | (h <= r.h_hi)
        return hue & (s >= r.s_lo) & (s <= r.s_hi) & (v >= r.v_lo) & (v <= r.v_hi)

    h, s, v = hsv.T
    want = np.zeros(len(hsv), int)
    for i, r in enumerate(c.classes.values()):
        want[(want == 0) & inside(r, h, s, v)] = i + 1
    bits = lut[0, h, 0] & lut[0, s, 1] & lut[0, v, 2]
    assert np.array_equal(label_lut[bits], want)
    assert np.array_equal(bug_lut[bits] == 255, inside(c.bug, h, s, v))
    assert np.array_equal(leaf_lut[bits] == 255, inside(c.leaf, h, s, v))
    assert len(set(want)) == 4  # the sample hit every class and the background
