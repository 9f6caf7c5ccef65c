"""Map files in map_server format: exact round trips, map_server's reading rules, and one clear
error naming file and field for every malformed file."""
from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from hw.errors import InputError
from nav.map_io import load_map, save_map, unknown_pixel
from nav.occupancy import OccupancyMap


def random_map(h=37, w=53, seed=0) -> OccupancyMap:
    rng = np.random.default_rng(seed)
    occ = rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(h, w))
    return OccupancyMap(occ, 0.05, -1.25, 3.5, 0.3)


def nav2_trinary(pixels: np.ndarray, occupied_thresh: float, free_thresh: float) -> np.ndarray:
    """Nav2 map_server's trinary rule, written out independently of nav.map_io (negate 0)."""
    occ = 1.0 - pixels / 255.0
    return np.where(occupied_thresh < occ, 100, np.where(occ < free_thresh, 0, -1))


@pytest.mark.parametrize("shape", [(37, 53), (1, 1), (64, 7)])
def test_save_load_save_is_bit_exact(tmp_path, shape):
    m = random_map(*shape)
    first = save_map(m, tmp_path / "a" / "map.yaml")
    back = load_map(first)
    assert np.array_equal(back.occupancy, m.occupancy) and back.occupancy.dtype == np.int8
    assert (back.resolution, back.origin_x, back.origin_y, back.origin_yaw) == (0.05, -1.25, 3.5, 0.3)
    second = save_map(back, tmp_path / "b" / "map.yaml")
    assert (tmp_path / "a" / "map.pgm").read_bytes() == (tmp_path / "b" / "map.pgm").read_bytes()
    assert first.read_text() == second.read_text()


def test_the_file_is_what_map_server_expects(tmp_path):
    occ = np.array([[100, 0], [-1, 70]], dtype=np.int8)  # row 0 is the south row
    path = save_map(OccupancyMap(occ, 0.05, 0.0, 0.0), tmp_path / "m.yaml")
    text = path.read_text()
    for line in ("image: m.pgm", "mode: trinary", "resolution: 0.05", "negate: 0",
                 "occupied_thresh: 0.65", "free_thresh: 0.25"):
        assert line in text
    img = cv2.imread(str(tmp_path / "m.pgm"), cv2.IMREAD_UNCHANGED)
    assert img.tolist() == [[128, 0], [0, 254]]  # the top row is the north row; 70 % is occupied


def test_our_unknown_grey_is_unknown_to_nav2_with_the_thresholds_we_write(tmp_path):
    """Why unknown is 128 and not map_saver's 205: Nav2 thresholds with the YAML's free_thresh
    (0.25), and 205 is p = 0.196 < 0.25, i.e. free."""
    occ = np.array([[-1, 0, 100, 40]], dtype=np.int8)
    save_map(OccupancyMap(occ, 0.05, 0.0, 0.0), tmp_path / "m.yaml")
    meta = yaml.safe_load((tmp_path / "m.yaml").read_text())
    pixels = cv2.imread(str(tmp_path / "m.pgm"), cv2.IMREAD_UNCHANGED)
    assert pixels.tolist() == [[128, 254, 0, 128]]
    assert nav2_trinary(pixels, meta["occupied_thresh"], meta["free_thresh"]).tolist() == [[-1, 0, 100, -1]]
    assert nav2_trinary(np.array([205]), meta["occupied_thresh"], meta["free_thresh"]).tolist() == [0]


def test_a_ros1_map_saver_file_reads_205_as_unknown_thanks_to_its_free_thresh(tmp_path):
    (tmp_path / "r1.pgm").write_bytes(b"P5\n# CREATOR: map_saver\n3 1\n255\n" + bytes([254, 205, 0]))
    (tmp_path / "r1.yaml").write_text("image: r1.pgm\nresolution: 0.050000\norigin: [-2.0, -3.5, 0.0]\n"
                                      "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n")
    assert load_map(tmp_path / "r1.yaml").occupancy.tolist() == [[0, -1, 100]]


def test_pixels_exactly_on_a_threshold_are_unknown_as_in_nav2(tmp_path):
    pixels = np.array([[101, 102, 153, 154]], dtype=np.uint8)  # p = .604, .6 exactly, .4 exactly, .396
    (tmp_path / "t.pgm").write_bytes(b"P5 4 1 255\n" + pixels.tobytes())
    (tmp_path / "t.yaml").write_text("image: t.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"
                                     "occupied_thresh: 0.6\nfree_thresh: 0.4\n")
    got = load_map(tmp_path / "t.yaml").occupancy
    assert got.tolist() == [[100, -1, -1, 0]]
    assert got.tolist() == nav2_trinary(pixels, 0.6, 0.4).tolist()


def test_other_thresholds_are_written_and_still_round_trip(tmp_path):
    m = random_map(20, 30, seed=3)
    path = save_map(m, tmp_path / "m.yaml", occupied_thresh=0.8, free_thresh=0.6)
    meta = yaml.safe_load(path.read_text())
    assert (meta["occupied_thresh"], meta["free_thresh"]) == (0.8, 0.6)
    grey = unknown_pixel(0.8, 0.6)
    assert 0.6 < 1 - grey / 255 < 0.8 and grey != 128  # 128 (p = .498) would read free here
    assert np.array_equal(load_map(path).occupancy, m.occupancy)
    assert unknown_pixel() == 128


@pytest.mark.parametrize("occupied, free", [(1.0, 0.25), (0.65, 0.0), (0.5, 0.5), (0.5, 0.499)])
def test_thresholds_that_cannot_round_trip_are_refused_on_save(tmp_path, occupied, free):
    with pytest.raises(ValueError):
        save_map(random_map(2, 2), tmp_path / "m.yaml", occupied_thresh=occupied, free_thresh=free)
    assert not (tmp_path / "m.yaml").exists() and not (tmp_path / "m.pgm").exists()


def test_a_hand_written_pgm_follows_map_servers_thresholds(tmp_path):
    pixels = bytes([0, 89, 90, 128, 191, 192, 254, 255])  # p = 1, .65, .647, .498, .251, .247, .004, 0
    (tmp_path / "h.pgm").write_bytes(b"P5\n# a comment\n8 1\n255\n" + pixels)
    (tmp_path / "h.yaml").write_text("image: h.pgm\nresolution: 0.1\norigin: [1, 2, 0]\n"
                                     "occupied_thresh: 0.65\nfree_thresh: 0.25\nnegate: 0\nmode: trinary\n")
    m = load_map(tmp_path / "h.yaml")
    assert m.occupancy.tolist() == [[100, 100, -1, -1, -1, 0, 0, 0]]
    assert (m.origin_x, m.origin_y, m.resolution) == (1.0, 2.0, 0.1)


def test_negate_raw_ascii_pgm_and_png(tmp_path):
    (tmp_path / "a.pgm").write_text("P2\n3 1\n255\n0 128 255\n")
    (tmp_path / "n.yaml").write_text("image: a.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 1\n")
    assert load_map(tmp_path / "n.yaml").occupancy.tolist() == [[0, -1, 100]]
    cv2.imwrite(str(tmp_path / "r.png"), np.array([[0, 55, 100, 101, 255]], dtype=np.uint8))
    (tmp_path / "r.yaml").write_text("image: r.png\nmode: raw\nresolution: 0.05\norigin: [0, 0, 0]\n")
    assert load_map(tmp_path / "r.yaml").occupancy.tolist() == [[0, 55, 100, -1, -1]]
    cv2.imwrite(str(tmp_path / "c.png"), np.dstack([np.full((2, 2), 254, np.uint8)] * 3))
    (tmp_path / "c.yaml").write_text(f"image: {tmp_path / 'c.png'}\nresolution: 0.05\norigin: [0, 0, 0]\n")
    assert (load_map(tmp_path / "c.yaml").occupancy == 0).all()  # absolute path, colour averaged
    # B, G, R average 191.33: p = 0.2497 < 0.25, free; rounding the grey to 191 first would not be
    cv2.imwrite(str(tmp_path / "e.png"), np.array([[[191, 191, 192]]], dtype=np.uint8))
    (tmp_path / "e.yaml").write_text("image: e.png\nresolution: 0.05\norigin: [0, 0, 0]\n")
    assert load_map(tmp_path / "e.yaml").occupancy.tolist() == [[0]]


GOOD = "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"


@pytest.mark.parametrize("text, needle", [
    ("image: [m.pgm\n", "not valid YAML"),
    ("- a list\n", "YAML mapping"),
    ("resolution: 0.05\norigin: [0, 0, 0]\n", "image: missing"),
    ("image: m.pgm\norigin: [0, 0, 0]\n", "resolution: missing"),
    (GOOD + "mode: scale\n", "mode: 'scale'"),
    ("image: m.pgm\nresolution: -0.05\norigin: [0, 0, 0]\n", "resolution: must be > 0"),
    ("image: m.pgm\nresolution: fine\norigin: [0, 0, 0]\n", "resolution: expected a number"),
    ("image: m.pgm\nresolution: 0.05\norigin: [0, 0]\n", "origin: must be three numbers"),
    ("image: m.pgm\nresolution: 0.05\n", "origin: missing"),
    (GOOD + "negate: true\n", "negate: expected a number"),
    (GOOD + "occupied_thresh: 1.5\n", "occupied_thresh: must be within [0, 1]"),
    (GOOD + "free_thresh: 0.7\n", "free_thresh: 0.7 must be below occupied_thresh"),
    (GOOD + "negate: 2\n", "negate: must be 0 or 1"),
    ("image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n", "gone.pgm does not exist"),
    ("image: .\nresolution: 0.05\norigin: [0, 0, 0]\n", "is not a file"),
])
def test_malformed_map_files_are_one_clear_error_naming_file_and_field(tmp_path, text, needle):
    (tmp_path / "m.pgm").write_bytes(b"P5 2 1 255\n\x00\xfe")
    (tmp_path / "bad.yaml").write_text(text)
    with pytest.raises(InputError) as err:
        load_map(tmp_path / "bad.yaml")
    assert str(tmp_path / "bad.yaml") in str(err.value) and needle in str(err.value)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("image, needle", [
    (b"P5 2 2 255\n\x00\xfe", "truncated: 2 of 4"),
    (b"P5 2 x 255\n", "bad PGM header"),
    (b"P5 2 2 65535\n" + bytes(8), "maxval 255"),
    (b"P5 2", "truncated PGM header"),
    (b"P2 2 1 255\n0 x\n", "not numbers"),
    (b"P2 2 1 255\n0\n", "1 pixels in 0..255, expected 2"),
    (b"not an image at all", "not a readable image"),
    (b"", "not a readable image"),
])
def test_corrupt_images_are_one_clear_error(tmp_path, image, needle):
    (tmp_path / "m.pgm").write_bytes(image)
    (tmp_path / "m.yaml").write_text(GOOD)
    with pytest.raises(InputError) as err:
        load_map(tmp_path / "m.yaml")
    message = str(err.value)
    assert needle in message and "\n" not in message
    assert message.startswith(f"{tmp_path / 'm.yaml'}: image: {tmp_path / 'm.pgm'}")


def test_an_unreadable_image_is_an_input_error(tmp_path, monkeypatch):
    (tmp_path / "m.pgm").write_bytes(b"P5 2 1 255\n\x00\xfe")
    (tmp_path / "m.yaml").write_text(GOOD)

    def denied(self):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(Path, "read_bytes", denied)
    with pytest.raises(InputError, match=r"m.yaml: image: .*m.pgm: cannot read \(Permission denied\)"):
        load_map(tmp_path / "m.yaml")


def test_a_missing_map_file_names_it(tmp_path):
    with pytest.raises(InputError, match="nope.yaml: map file not found"):
        load_map(tmp_path / "nope.yaml")


def test_a_duplicate_key_in_a_map_file_is_refused_not_silently_overridden(tmp_path):
    (tmp_path / "m.yaml").write_text("image: m.pgm\nresolution: 0.05\nresolution: 0.1\norigin: [0, 0, 0]\n")
    with pytest.raises(InputError, match="duplicate key 'resolution'"):
        load_map(tmp_path / "m.yaml")
