"""Pests on leaves (issue 30): a patrol reports a pest on a leaf of a plant with no bloom and on
a leaf of a flowering plant, and no pest on a clean plant beside them. The smallest greenhouse
that shows it: one row of three pots, the sim told to put every pest on a leaf."""
from __future__ import annotations

import time

import pytest

from mission.jobs.patrol import run_to_end
from mission.jobs.sim_patrol import start_sim_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import load_config
from sim.generate import generate_world
from sim.pests import pest_site

pytestmark = pytest.mark.slow

PLANTS = {"P01": ("none", 1, True), "P02": ("red", 2, True), "P03": ("white", 3, False)}


def test_pests_on_leaves_of_flowering_and_bare_plants_are_reported(tmp_path):
    world = generate_world(1, 3, 6)
    world = world.model_copy(update={"pots": [
        p.model_copy(update=dict(zip(("flower", "blooms", "bug"), PLANTS[p.id]))) for p in world.pots]})
    config = load_config(env={"LUPIN_SIM__GEOMETRY__LEAF_PEST_SHARE": "1"})
    share = config.sim.geometry.leaf_pest_share
    assert [pest_site(world.name, p, share) and pest_site(world.name, p, share).on for p in world.pots] == [
        "leaf", "leaf", None]
    doc = run_to_end(start_sim_patrol(world, mission_from_world(world), config, tmp_path / "r.json",
                                      time.perf_counter))
    assert doc["outcome"] == "completed"
    for p in doc["pots"]:
        flower, blooms, bug = PLANTS[p["id"]]
        assert p["status"] == "inspected", p["id"]
        assert (p["flower"]["color"], p["flower"]["bug"]) == (flower, bug), p["id"]
        assert p["flower"]["blooms"] == (0 if flower == "none" else blooms), p["id"]
    bugs = {a["pot"]: a["detail"] for a in doc["anomalies"] if a["kind"] == "bug"}
    assert set(bugs) == {"P01", "P02"}
    assert all(d.startswith("dark spot on a leaf (confidence ") for d in bugs.values()), bugs
