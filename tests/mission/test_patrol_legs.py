"""A patrol longer than one battery (issue 31): home before the reserve, charge on the dock, the
rest in a fresh order; a pack draining faster than the model sends it home at once; a robot
that may not charge ends at the dock naming what is left, and a report's undone pots resume.

The sim's pack is made small (config) so that a few pots of the built-in greenhouse need more
than one charge: the smallest runs that prove each point. Charge is judged on the sim's true
pack, never on the robot's own estimate.
"""
from __future__ import annotations

import json
import math
import time
from pathlib import Path

import pytest
import yaml

from lupin.cli import main
from mission.history.store import open_history
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.events_file import parse_events
from mission.patrol.mission_file import dump_mission, mission_from_world
from mission.runtime.config import load_config, with_overrides
from sim.world import load_default_world

SMALL_PACK = {"sim": {"battery": {"capacity_ah": 0.03}}}
"""A pack for about two pots of the built-in greenhouse and the way back (~1/70 of the real one)."""
NEAR = ("P01", "P02", "P05")


def near_mission(ids=NEAR):
    m = mission_from_world(load_default_world())
    return m.model_copy(update={"pots": [p for p in m.pots if p.id in ids]})


def patrol(tmp_path: Path, overrides: dict, events: list = (), ids=NEAR, history=None):
    """One patrol to its end; the report, the sim's lowest true charge, the robot's distance
    from the dock at the end (truth)."""
    world = load_default_world()
    config = with_overrides(load_config(env={}), overrides)
    script = parse_events(list(events), "events", config, world)
    run = start_sim_patrol(world, near_mission(ids), config, tmp_path / "report.json", time.perf_counter, script,
                           history=history)
    pack, lowest = run.sim.sim.battery, 1.0
    try:
        while not run.done:
            run.step()
            lowest = min(lowest, pack.charge)
        doc = run.finish(run.outcome())
        truth, dock = run.sim.sim.truth(), world.dock_pose
    finally:
        run.close()
        if run.history is not None:
            run.history.wait()
    return doc, lowest, math.hypot(truth.x - dock.x, truth.y - dock.y)


@pytest.mark.slow
def test_a_patrol_longer_than_the_battery_goes_home_charges_and_finishes_every_pot(tmp_path):
    history = open_history(str(tmp_path / "h.db"))
    doc, lowest, off_dock = patrol(tmp_path, SMALL_PACK, history=history)
    assert doc["outcome"] == "completed"
    assert [p["status"] for p in doc["pots"]] == ["inspected"] * 3
    first, second = doc["legs"]
    assert "reserve" in first["why_home"] and first["charge_returned"] >= 0.15
    assert first["charge_after"] >= 0.95 and second["left_s"] >= first["charged_s"] > first["returned_s"]
    assert first["pots"] + second["pots"] == 3 and second["returned_s"] is not None
    assert lowest >= 0.15  # the true pack never went below the reserve
    assert doc["energy"]["charges"] == 1 and off_dock < 0.3
    rows = history.legs(doc["history"]["patrol"])
    assert [(r["leg"], r["pots"]) for r in rows] == [(1, first["pots"]), (2, second["pots"])]
    assert rows[0]["charge_after"] == first["charge_after"]
    history.close()


@pytest.mark.slow
def test_a_pack_draining_mid_aisle_sends_the_robot_home_at_once(tmp_path):
    drain = {"at": 5.0, "do": "battery_drain", "load": 30.0, "duration": 4.0}  # a stuck wheel, 30 A for 4 s
    config = {"sim": {"battery": {"capacity_ah": 0.05}}, "patrol": {"energy": {"charge": False}}}
    doc, lowest, off_dock = patrol(tmp_path, config, [drain], ids=("P04",))  # the far end of the first aisle
    leg, = doc["legs"]
    assert "faster than planned" in leg["why_home"]
    assert 5.0 < leg["headed_home_s"] <= 5.0 + 4.0 + 1.5  # within a check (1 s) and a reading (0.5 s) of the fall
    assert doc["outcome"] == "battery_low" and off_dock < 0.3 and lowest > 0.0


@pytest.mark.slow
def test_no_charge_ends_at_the_dock_listing_the_rest_and_resume_patrols_exactly_them(tmp_path, capsys):
    config = tmp_path / "small.yaml"
    config.write_text(yaml.safe_dump(SMALL_PACK))
    mission = tmp_path / "m.yaml"
    mission.write_text(dump_mission(near_mission()))
    first = tmp_path / "first" / "report.json"
    assert main(["--config", str(config), "patrol", "--mission", str(mission), "--report", str(first),
                 "--no-charge", "--history", "none"]) == 1
    out = capsys.readouterr().out
    doc = json.loads(first.read_text())
    left = [p["id"] for p in doc["pots"] if p["status"] == "skipped"]
    assert doc["outcome"] == "battery_low" and left and len(doc["legs"]) == 1
    assert f"left ({', '.join(left)})" in out and "no-charge" in out and "  leg 1: left 3 s (100%), back " in out
    resumed = tmp_path / "resume.yaml"
    assert main(["mission", "resume", str(first), "-o", str(resumed)]) == 0
    assert [p["id"] for p in yaml.safe_load(resumed.read_text())["pots"]] == left
    second = tmp_path / "second" / "report.json"
    assert main(["patrol", "--resume", str(first), "--report", str(second), "--history", "none"]) == 0
    assert [(p["id"], p["status"]) for p in json.loads(second.read_text())["pots"]] == [(i, "inspected") for i in left]


@pytest.mark.slow
def test_a_robot_that_cannot_reach_the_dock_stops_clear_of_the_aisles_and_says_where(tmp_path):
    drain = {"at": 5.0, "do": "battery_drain", "load": 30.0, "duration": 6.0}  # the pack all but empties
    config = {"sim": {"battery": {"capacity_ah": 0.05}}}
    doc, lowest, off_dock = patrol(tmp_path, config, [drain], ids=("P04",))
    assert doc["outcome"] == "battery_low" and off_dock > 0.3
    assert "stopped clear of the aisles at" in doc["notes"]["battery"]
    x, y = (float(v) for v in doc["notes"]["battery"].split(" at (")[1].split(")")[0].split(", "))
    world = load_default_world()  # map frame = world frame less the spawn (1.0, 0.5, yaw 0)
    wx, wy = x + world.spawn.x, y + world.spawn.y
    assert wx < 1.0 or wx > 6.0 or wy < 0.8  # not between the rows (pots at x 2..5), nor at an aisle's mouth
