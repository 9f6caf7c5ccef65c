"""Map files in map_server format: exact round trips, map_server's reading rules, and one clear
error naming file and field for every malformed file."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from hw.errors import InputError
from nav.map_io import load_map, save_map
from nav.occupancy import OccupancyMap


def random_map(h=37, w=53, seed=0) -> OccupancyMap:
    rng = np.random.default_rng(seed)
    occ = rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(h, w))
    return OccupancyMap(occ, 0.05, -1.25, 3.5, 0.0)


@pytest.mark.parametrize("shape", [(37, 53), (1, 1), (64, 7)])
def test_save_load_save_is_bit_exact(tmp_path, shape):
    m = random_map(*shape)
    first = save_map(m, tmp_path / "a" / "map.yaml")
    back = load_map(first)
    assert np.array_equal(back.occupancy, m.occupancy) and back.occupancy.dtype == np.int8
    assert (back.resolution, back.origin_x, back.origin_y, back.origin_yaw) == (0.05, -1.25, 3.5, 0.0)
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
    (GOOD + "occupied_thresh: 1.5\n", "occupied_thresh: must be within [0, 1]"),
    (GOOD + "free_thresh: 0.7\n", "free_thresh: 0.7 must be below occupied_thresh"),
    (GOOD + "negate: 2\n", "negate: must be 0 or 1"),
    ("image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n", "image: "),
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
    (b"not an image at all", "not a readable image"),
])
def test_corrupt_images_are_one_clear_error(tmp_path, image, needle):
    (tmp_path / "m.pgm").write_bytes(image)
    (tmp_path / "m.yaml").write_text(GOOD)
    with pytest.raises(InputError, match=needle):
        load_map(tmp_path / "m.yaml")


def test_a_missing_map_file_names_it(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        load_map(tmp_path / "nope.yaml")
