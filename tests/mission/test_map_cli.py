"""`lupin map save|show`: a map made by SLAM in the sim, saved in map_server format, shown."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from lupin.cli import main
from nav.map_io import load_map, save_map
from nav.map_render import GRID, render_map
from nav.occupancy import OccupancyMap
from sim.world import dump_world, parse_world


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def one_row_world(tmp_path):
    """A 5 x 3 m greenhouse with one row of two pots: a short survey."""
    w = parse_world({"name": "tiny", "floor": {"x": 5.0, "y": 3.0}, "spawn": {"x": 1.0, "y": 0.6, "yaw": 0.0},
                     "pots": [{"id": "A", "x": 2.0, "y": 1.5, "facing": -1.5708, "tag": 1, "flower": "red"},
                              {"id": "B", "x": 3.0, "y": 1.5, "facing": -1.5708, "tag": 2, "flower": "pink"}]},
                    "tiny")
    path = tmp_path / "tiny.yaml"
    path.write_text(dump_world(w))
    return path


@pytest.mark.slow
def test_map_save_surveys_the_greenhouse_with_slam_and_writes_a_loadable_map(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("LUPIN_NAV__SLAM", "false")  # set up to localise elsewhere: map save still maps
    monkeypatch.setenv("LUPIN_NAV__MAP_FILE", str(tmp_path / "elsewhere.yaml"))
    code, out, err = run(capsys, "map", "save", "--world", str(one_row_world(tmp_path)), "-o", str(tmp_path / "m" / "tiny.yaml"))
    assert code == 0, err
    assert "keyframes" in out and "tiny.yaml" in out
    m = load_map(tmp_path / "m" / "tiny.yaml")
    assert (tmp_path / "m" / "tiny.pgm").is_file()
    # cropped to what was explored, about the 5 x 3 m floor plus walls, in the dock's frame
    assert 4.5 < m.width * m.resolution < 7.0 and 2.5 < m.height * m.resolution < 5.0
    ix, iy = m.geometry.cell_of([2.0 - 1.0], [1.5 - 0.6 - 0.11])  # pot A's south face, map frame
    near = m.occupancy[iy[0] - 1:iy[0] + 2, ix[0] - 1:ix[0] + 2]
    assert (near >= 65).any()
    ix, iy = m.geometry.cell_of([0.5], [0.0])  # the aisle ahead of the dock: free
    assert m.occupancy[iy[0], ix[0]] == 0


def test_map_show_prints_a_summary_and_renders(capsys, tmp_path):
    occ = np.full((40, 60), -1, np.int8)
    occ[5:35, 5:55] = 0
    occ[5, 5:55] = 100
    save_map(OccupancyMap(occ, 0.05, -0.5, -0.5), tmp_path / "m.yaml")
    code, out, err = run(capsys, "map", "show", str(tmp_path / "m.yaml"))
    assert code == 0
    assert "60 x 40 cells" in out and "occupied 50 (2.1 %)" in out and not list(tmp_path.glob("*.png"))
    code, out, err = run(capsys, "map", "show", str(tmp_path / "m.yaml"), "-o", str(tmp_path / "m.png"))
    assert code == 0 and "wrote" in out
    img = cv2.imread(str(tmp_path / "m.png"))
    assert img.shape[0] >= 400 and img.shape[1] == img.shape[0] * 60 // 40
    assert (img == 0).all(axis=2).any() and (img == 255).all(axis=2).any()


def test_the_rendering_is_north_up_with_the_origin_marked_when_it_is_on_the_map():
    occ = np.zeros((40, 60), np.int8)  # 3 x 2 m, all free
    occ[-1, :] = 100  # the north row (highest iy) is a wall
    occ[:, 0] = -1  # the west column unknown
    img = render_map(OccupancyMap(occ, 0.05, -0.5, -0.5))
    assert img.dtype == np.uint8 and img.shape == (400, 600, 3)  # 10 px per cell, short side 400
    assert (img[:10, 10:] == 0).all()  # the top band is the wall, solid black
    assert (img[10:, :10] == img[20, 5]).all() and 100 < img[20, 5, 0] < 200  # unknown: one grey
    assert (img[210, 250] == 255).all()  # free, off the grid lines
    assert (img[250, 300] == GRID).all() and (img[100, 250] == GRID).all()  # the x = 1 m and y = 1 m lines

    def red(i):
        return ((i[:, :, 2] > 180) & (i[:, :, 1] < 80)).sum()

    def green(i):
        return ((i[:, :, 1] > 150) & (i[:, :, 2] < 80)).sum()

    # origin (0, 0) is 0.5 m in from the south-west corner: column 100, row 300; x points east
    assert red(img) > 50 and green(img) > 50
    assert red(img[295:306, 100:160]) > 20 and green(img[240:301, 95:106]) > 20
    away = render_map(OccupancyMap(occ, 0.05, 5.0, 5.0))
    assert red(away) == 0 and green(away) == 0


def test_a_long_thin_map_renders_at_a_sane_size():
    img = render_map(OccupancyMap(np.zeros((2, 1000), np.int8), 0.05, 0.0, 0.0))
    assert img.shape[1] <= 4000 and img.shape[0] == 2 * (img.shape[1] // 1000)
    assert render_map(OccupancyMap(np.zeros((3, 5), np.int8), 0.05, 0.0, 0.0), scale=2).shape == (6, 10, 3)


def test_map_show_writes_nothing_when_the_output_directory_is_missing(capsys, tmp_path):
    save_map(OccupancyMap(np.zeros((3, 3), np.int8), 0.05, 0.0, 0.0), tmp_path / "m.yaml")
    code, out, err = run(capsys, "map", "show", str(tmp_path / "m.yaml"), "-o", str(tmp_path / "no" / "m.png"))
    assert code == 2 and out == "" and "does not exist" in err and len(err.strip().splitlines()) == 1
    (tmp_path / "dir.png").mkdir()  # a directory where the PNG should go: cv2 cannot write it
    code, out, err = run(capsys, "map", "show", str(tmp_path / "m.yaml"), "-o", str(tmp_path / "dir.png"))
    assert code == 2 and "cannot write the PNG" in err and "wrote" not in out


@pytest.mark.parametrize("argv, needle", [
    (["map", "show", "missing.yaml"], "map file not found"),
    (["map", "show", "BAD"], "not valid YAML"),
    (["map", "show", "NOIMAGE"], "image: "),
    (["map", "show", "GOOD", "-o", "x.jpg"], "must be a .png"),
    (["map", "save", "-o", "map.png"], "NAME.yaml"),
])
def test_bad_map_input_is_exit_2_and_one_line(capsys, tmp_path, argv, needle):
    (tmp_path / "bad.yaml").write_text("image: [x\n")
    (tmp_path / "noimage.yaml").write_text("image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    save_map(OccupancyMap(np.zeros((3, 3), np.int8), 0.05, 0.0, 0.0), tmp_path / "good.yaml")
    files = {"BAD": "bad.yaml", "NOIMAGE": "noimage.yaml", "GOOD": "good.yaml"}
    argv = [str(tmp_path / files[a]) if a in files else a for a in argv]
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert needle in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


@pytest.mark.slow
def test_localisation_on_a_bad_saved_map_is_exit_2_before_the_robot_moves(capsys, tmp_path, monkeypatch):
    (tmp_path / "bad.yaml").write_text("image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    monkeypatch.setenv("LUPIN_NAV__SLAM", "false")
    monkeypatch.setenv("LUPIN_NAV__MAP_FILE", str(tmp_path / "bad.yaml"))
    code, out, err = run(capsys, "sim", "navigate", "--to", "3.0,0.5,0")
    assert code == 2 and "bad.yaml: image:" in err and len(err.strip().splitlines()) == 1
    monkeypatch.delenv("LUPIN_NAV__MAP_FILE")
    code, out, err = run(capsys, "sim", "navigate", "--to", "3.0,0.5,0")
    assert code == 2 and "map_file is not set" in err
