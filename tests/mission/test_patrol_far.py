"""A greenhouse longer than the old fixed 24 m map: the pots at the far end, more than 20 m from
the dock, are reached and inspected (the maps grow to take them in)."""
from __future__ import annotations

import json
import math

import pytest

from lupin.cli import main
from mission.patrol.mission_file import dump_mission, mission_from_world
from sim.generate import generate_world
from sim.world import dump_world

pytestmark = pytest.mark.slow


def test_pots_more_than_20_m_from_the_dock_are_inspected(tmp_path, capsys):
    world = generate_world(1, 23, 5)  # one row, 25 m long
    m = mission_from_world(world)
    far = [p for p in m.pots if math.hypot(p.x, p.y) > 20.0]
    assert len(far) >= 2
    (tmp_path / "w.yaml").write_text(dump_world(world))
    (tmp_path / "m.yaml").write_text(dump_mission(m.model_copy(update={"pots": far[-2:]})))
    report = tmp_path / "r" / "report.json"
    assert main(["patrol", "--world", str(tmp_path / "w.yaml"), "--mission", str(tmp_path / "m.yaml"),
                 "--report", str(report)]) == 0
    doc = json.loads(report.read_text())
    assert [p["status"] for p in doc["pots"]] == ["inspected", "inspected"]
    assert all(p["tag_read"] == p["tag_expected"] and p["truth_error"]["xy"] < 0.1 for p in doc["pots"])
    assert doc["distance_m"] > 40.0  # out past 20 m and home again
    assert "map.yaml" in {f.name for f in report.parent.iterdir()}
    capsys.readouterr()
