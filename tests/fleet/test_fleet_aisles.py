"""Two robots' real patrols into one aisle, on ``lupin fleet sim``'s robots (one MuJoCo world, a
runtime each in lock-step, each link on the TLS router under its certificate) with the
dispatcher's arbiter on the router: each patrol is started as the dispatcher starts one
(``mission_start`` with the fleet's aisles as outlines in the robot's own frame), both need the
middle aisle of the 3 x 4 greenhouse at once (or each inspects in one aisle and goes on to the
other's), and judged on ground truth the two robots are never in one aisle together, and both
inspect their pots and come home."""
from __future__ import annotations

import json
import math
import threading
import time

import numpy as np
import pytest

from behaviours.aisles import EnterAisles
from fleet.aisle_locks import AisleLockServer
from fleet.aisles import find_aisles, outlines
from fleet.certs import member_files
from fleet.fleet_map import plan_of_world
from mission.jobs.fleet_sim import run_fleet, start_fleet_sim
from mission.link.fleet_link import FleetLink
from mission.patrol.aisle_outlines import NO_AISLE, AisleOutlines
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world
from tests.fleet.conftest import member, wait_for

pytestmark = pytest.mark.slow

ONE_AISLE = {"r1": ["P08"], "r2": ["P05"]}
"""The middle aisle's (between the rows at y 2 and 3) east and west end pots, from docks at its west."""
CROSSED = {"r1": ["P07", "P03"], "r2": ["P02", "P06"]}
"""Each robot inspects in one aisle (the middle one, the south strip) and goes on to the other's:
a deadlock's shape, when each asks from inside its own."""


def _in_frame(polygon: np.ndarray, dock) -> list[list[float]]:
    c, s = math.cos(dock.yaw), math.sin(dock.yaw)
    d = polygon - (dock.x, dock.y)
    return np.c_[c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]].tolist()


def test_two_patrols_into_one_aisle_take_turns(router, certs, tmp_path):
    waited = _patrols(ONE_AISLE, router, certs, tmp_path)
    assert waited, "no robot ever waited for the aisle: the test did not test it"


def test_two_patrols_each_going_on_to_the_aisle_the_other_is_in_both_finish(router, certs, tmp_path):
    _patrols(CROSSED, router, certs, tmp_path)


def _patrols(pots_of: dict[str, list[str]], router, certs, tmp_path) -> set[str]:
    """Each robot patrols its pots; asserts they never share an aisle and all complete, and
    returns the robots that waited outside an aisle."""
    world = generate_world(3, 4, 1, robots=2)
    pots = np.array([(p.x, p.y, p.facing) for p in world.pots])
    shapes = outlines(find_aisles(plan_of_world(world, (0.0, 0.0, 0.0)), pots))  # the world's frame
    judge = AisleOutlines(shapes)
    config = with_overrides(LupinConfig(), {"sim": {"realtime": False, "seed": 1}, "link": {"command_timeout": 60.0}})
    fleet = start_fleet_sim(world, config, ["r1", "r2"], tmp_path, time.perf_counter)
    fleet.join(router, lambda name: member_files(certs, name), None)
    dispatcher = member(router, certs, "dispatcher")
    arbiter = AisleLockServer(dispatcher, time.monotonic)
    together, waited = [], set()

    def watch(now: float) -> None:  # judging only: ground truth, and what each tree is doing
        truths = fleet.scene.truths()
        inside = {r: int(judge.at([p.x, p.y])[0]) for r, p in truths.items()}
        if inside["r1"] != NO_AISLE and inside["r1"] == inside["r2"]:
            together.append((round(now, 2), inside))
        for r, s in fleet.services.items():
            if s.run is not None and any(isinstance(n, EnterAisles) and n.feedback_message.startswith("waiting outside")
                                         for n in s.run.tree.root.iterate()):
                waited.add(r)

    fleet.services["r1"].robot.scheduler.every("judge aisles", 20.0, watch)
    stop = threading.Event()
    stepping = threading.Thread(target=run_fleet, args=(fleet, stop), daemon=True)
    stepping.start()
    console = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=60.0)  # a patrol starts slowly
    try:
        assert wait_for(lambda: console.robots() == ["r1", "r2"] and arbiter.roster.robots() == ["r1", "r2"], 60)
        for k, r in enumerate(("r1", "r2")):
            mine = world.for_robot(k)
            m = mission_from_world(mine)
            m = m.model_copy(update={"pots": [p for i in pots_of[r] for p in m.pots if p.id == i], "order": "as_listed"})
            aisles = {str(a): _in_frame(poly, mine.spawn) for a, poly in shapes.items()}
            assert console.client(r).send("mission_start", mission=m.model_dump(mode="json"), aisles=aisles) is None
        assert wait_for(lambda: all(s.outcome for s in fleet.services.values()), 400), \
            f"not done: {[s.run.tree.current_step() for s in fleet.services.values() if s.run is not None]}"
        assert together == [], f"two robots in one aisle: {together[:5]}"
        for r, s in fleet.services.items():
            report = json.loads(s.report_path.read_text())
            assert s.outcome == "completed", (r, report.get("reason"), report.get("notes"), [(p["id"], p["status"]) for p in report["pots"]])
            assert sorted((p["id"], p["status"]) for p in report["pots"]) == sorted((p, "inspected") for p in pots_of[r])
            assert (report["aisles"]["wait_s"] > 0) == (r in waited), report["aisles"]  # the report says who waited
        assert wait_for(lambda: arbiter.table.held() == {})  # home, both let go
        return waited
    finally:
        console.close()
        arbiter.close()
        stop.set()
        stepping.join(60)
        dispatcher.close()
