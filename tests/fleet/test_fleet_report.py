"""fleet.json and fleet.png (fleet/fleet_report.py) from robots' reports: who did what, who
handed what over and why, the makespan, and whether every pot was inspected."""
from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

from fleet.fleet_report import COLOURS, RobotRun, fleet_summary, write_fleet_report
from nav.occupancy import OccupancyMap
from tests.nav.builders import RES, greenhouse_occupancy

POTS = {f"P{k:02d}": (2.0 + (k - 1) % 4, 1.0 + (k - 1) // 4) for k in range(1, 13)}


def report(done: list[str], failed: list[str] = (), time_s: float = 100.0, outcome: str = "completed") -> dict:
    pots = [{"id": p, "status": "inspected"} for p in done] + [{"id": p, "status": "failed"} for p in failed]
    return {"mission": "m", "outcome": outcome, "sim_time_s": time_s, "pots": pots}


def runs_with_a_handover() -> list[RobotRun]:
    ids = list(POTS)
    r1 = RobotRun("r1", ids[:4], report(ids[:4], time_s=90.0), path_xy=np.array([[1.0, 0.5], [5.0, 0.5]]))
    r2 = RobotRun("r2", ids[4:8], report(ids[4:5], time_s=30.0, outcome="aborted"), handed_over=ids[5:8],
                  handover_reason="liveliness")
    r3 = RobotRun("r3", ids[8:] + ids[5:8], report(ids[8:] + ids[5:8], time_s=140.0), received=ids[5:8],
                  path_xy=np.array([[1.0, 2.5], [5.0, 2.5], [5.0, 1.5]]))
    return [r1, r2, r3]


def test_the_summary_counts_each_robot_and_the_fleet():
    s = fleet_summary("m", list(POTS), runs_with_a_handover())
    assert s["makespan_s"] == 140.0 and s["complete"] and s["pots"] == {"total": 12, "inspected": 12, "not_inspected": []}
    r2 = s["robots"]["r2"]
    assert r2["done"] == ["P05"] and r2["handed_over"] == ["P06", "P07", "P08"] and r2["handover_reason"] == "liveliness"
    assert s["robots"]["r3"]["received"] == ["P06", "P07", "P08"] and s["robots"]["r3"]["report"] == "r3/report.json"
    runs = runs_with_a_handover()
    runs[2].report = report(list(POTS)[8:], failed=["P06"], time_s=120.0)
    s = fleet_summary("m", list(POTS), runs)
    assert not s["complete"] and s["pots"]["not_inspected"] == ["P06", "P07", "P08"] and s["makespan_s"] == 120.0
    runs[1].handover_reason = "tired"
    with pytest.raises(ValueError, match="tired"):
        fleet_summary("m", list(POTS), runs)


def test_fleet_json_and_png_are_written_and_the_picture_shows_each_robots_colour(tmp_path):
    occ = OccupancyMap(greenhouse_occupancy(), RES, 0.0, 0.0)
    runs = runs_with_a_handover()
    s = write_fleet_report(tmp_path / "fleet", "m", POTS, runs, occ)
    assert json.loads((tmp_path / "fleet" / "fleet.json").read_text()) == s
    img = cv2.imread(str(tmp_path / "fleet" / "fleet.png"))
    assert img is not None and img.shape[0] > occ.height
    for k in range(3):  # every robot's colour is on the picture (its pots, its path, the legend)
        assert (np.abs(img.astype(int) - COLOURS[k]).sum(axis=2) < 30).sum() > 50
    # no map: a blank canvas round the paths and pots
    write_fleet_report(tmp_path / "blank", "m", POTS, runs)
    assert cv2.imread(str(tmp_path / "blank" / "fleet.png")) is not None
