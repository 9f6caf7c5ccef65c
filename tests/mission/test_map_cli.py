"""`lupin map save|show`: a map made by SLAM in the sim, saved in map_server format, shown."""
from __future__ import annotations

import cv2
import numpy as np
import pytest

from mission.cli import main
from nav.map_io import load_map, save_map
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


def test_map_save_surveys_the_greenhouse_with_slam_and_writes_a_loadable_map(capsys, tmp_path):
    code, out, err = run(capsys, "map", "save", "--world", str(one_row_world(tmp_path)), "-o", str(tmp_path / "m" / "tiny.yaml"))
    assert code == 0, err
    assert "keyframes" in out and "tiny.yaml" in out
    m = load_map(tmp_path / "m" / "tiny.yaml")
    assert (tmp_path / "m" / "tiny.pgm").is_file()
    # cropped to what was explored, about the 5 x 3 m floor plus walls, in the dock's frame
    assert 4.5 < m.width * m.resolution < 7.0 and 2.5 < m.height * m.resolution < 5.0
    ix, iy = m.cell_of([2.0 - 1.0], [1.5 - 0.6 - 0.11])  # pot A's south face, map frame
    near = m.occupancy[iy[0] - 1:iy[0] + 2, ix[0] - 1:ix[0] + 2]
    assert (near >= 65).any()
    ix, iy = m.cell_of([0.5], [0.0])  # the aisle ahead of the dock: free
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


@pytest.mark.parametrize("argv, needle", [
    (["map", "show", "missing.yaml"], "does not exist"),
    (["map", "show", "BAD"], "not valid YAML"),
    (["map", "show", "GOOD", "-o", "x.jpg"], "must be a .png"),
    (["map", "save", "-o", "map.png"], "NAME.yaml"),
])
def test_bad_map_input_is_exit_2_and_one_line(capsys, tmp_path, argv, needle):
    (tmp_path / "bad.yaml").write_text("image: [x\n")
    save_map(OccupancyMap(np.zeros((3, 3), np.int8), 0.05, 0.0, 0.0), tmp_path / "good.yaml")
    argv = [{"BAD": str(tmp_path / "bad.yaml"), "GOOD": str(tmp_path / "good.yaml")}.get(a, a) for a in argv]
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert needle in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_localisation_on_a_bad_saved_map_is_exit_2_before_the_robot_moves(capsys, tmp_path, monkeypatch):
    (tmp_path / "bad.yaml").write_text("image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    monkeypatch.setenv("LUPIN_NAV__SLAM", "false")
    monkeypatch.setenv("LUPIN_NAV__MAP_FILE", str(tmp_path / "bad.yaml"))
    code, out, err = run(capsys, "sim", "navigate", "--to", "3.0,0.5,0")
    assert code == 2 and "bad.yaml: image:" in err and len(err.strip().splitlines()) == 1
    monkeypatch.delenv("LUPIN_NAV__MAP_FILE")
    code, out, err = run(capsys, "sim", "navigate", "--to", "3.0,0.5,0")
    assert code == 2 and "map_file is not set" in err
