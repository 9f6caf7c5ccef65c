"""``fleet.patrol``: the fleet patrol on ``patrol.large``'s 180-pot two-bay greenhouse with 1, 2 and
3 robots (issue 34's figures); ``fleet.patrol_small``: the same on a 4 x 6 greenhouse of 24 pots,
a run that fits a coffee break.

Each run is the real thing as a user starts it, in one process: ``lupin fleet sim``'s robots
(``mission.jobs.fleet_sim``: one MuJoCo world, a runtime per robot in lock-step, as fast as the
machine allows), a TLS router with the fleet's access control, and ``lupin fleet patrol``'s
dispatcher (``fleet.fleet_patrol``) following them to the end. Figures per robot count:

* ``makespan_s``: the fleet's robot time to the last robot home (``fleet.json``), and for 2 and 3
  robots its share of the one robot's (goal: 3 robots <= 0.40);
* ``pots_right``: pots inspected with the tag, flower colour and pest flag the world file has
  (``lupin.bench.patrol.correct_pots``) over every report of the run, out of ``pots``;
* ``robot_contacts``: chassis-to-chassis contacts that began (``mission.jobs.contacts.robot_contact_log``,
  ground truth before every physics chunk; a contact held is one), goal 0;
* ``head_on``: meetings head-on in an aisle (two robots' true centres in one aisle of the world's
  plan, ``fleet.aisles``, closing on each other, each moving towards the other; a meeting held is
  one), goal 0;
* ``aisle_wait_s``: per robot, robot seconds its patrol waited for an aisle lock, when its patrol
  says (null: the patrol does not ask for locks);
* ``wall_s`` and ``peak_rss_mb`` (this process's peak so far: the runs go 1, 2, 3 robots, so the
  3-robot figure is the fleet's, goal <= 3 GB).

``fleet.handover``: the 3-robot run again with r2 dying a third of the way through its patrol
(``Death``: its link closes, so its liveliness token goes, and it stands where it is, as a robot
whose computer died, an obstacle where it stands: a contact with it counts): pots right (goal
all), pots handed over, and its makespan against the undisturbed 3-robot run (shared with ``fleet.patrol`` in one ``lupin bench`` process);
``fleet.handover_small`` the same on the small greenhouse. r2 dies the moment its report counts
a third of its pots: standing at the approach of the pot it has just inspected, whose result dies
with it (no fetch can come between). That pot is handed over with the rest, and the robot it goes
to cannot stand where r2 stands: it looks at the pot from beside r2 (``mission.patrol.aside``; r2,
silent, is kept out of by less, ``nav.costmap.robots``). Before that, on ``fleet.handover_small``
r3 tried P20 four times ("goal blocked beyond tolerance") and the run ended 23/24; now P20 is
inspected from 0.57 m off its approach pose and the run ends 24/24 (``fleet.handover``: 179/180
before, 180/180 after).

Every run is counted; a run that did not end within ``DEADLINE_S`` of wall time says so
(``complete`` false) with the figures it got.
"""
from __future__ import annotations

import json
import resource
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from fleet.aisles import NO_AISLE, find_aisles
from fleet.certs import make_fleet, member_files
from fleet.fleet_map import plan_of_world
from fleet.fleet_patrol import Inputs, world_docks
from fleet.fleet_patrol import fleet_patrol as dispatch
from fleet.members import read_members
from fleet.router import open_router
from lupin.bench import Sample, benchmark
from lupin.bench.patrol import LARGE, correct_pots
from mission.jobs.contacts import robot_contact_log
from mission.jobs.fleet_sim import start_fleet_sim
from mission.link.session import free_endpoint
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world
from sim.world import World

ROBOTS = (1, 2, 3)
SMALL = (4, 6, 1, 1)
"""rows, pots per row, seed, bays of ``fleet.patrol_small``'s greenhouse: 24 pots."""
JUDGE_RATE = 10.0
"""Ground-truth samples per robot second: a contact or a meeting lasts longer than 0.1 s."""
MEETING_M = 1.5
"""Two robots in one aisle closer than this, closing, meet head-on: neither can pass."""
MOVING = 0.05
"""Speed, m/s, below which a robot stands still for the head-on judge: a robot stopped dead
(``fleet.handover``'s r2) jitters in the physics by far less (0.1 mm a sample), and with no floor
at all any jitter towards a robot coming its way is a meeting, on and off: one ``fleet.handover``
run with r2 dead in an aisle counted 27."""
DEADLINE_S = 3 * 3600.0
KILLED, KILL_AT = "r2", 1 / 3
_RUNS: dict = {}


class FleetJudge:
    """Ground truth on the fleet sim's thread: head-on meetings in aisles, sampled at ``JUDGE_RATE``."""

    def __init__(self, scene, world: World):
        self.scene = scene
        pots = np.array([(p.x, p.y, p.facing) for p in world.pots])
        self.aisles = find_aisles(plan_of_world(world, (0.0, 0.0, 0.0)), pots)
        self.head_on = 0
        self._meeting: set = set()
        self._last: dict = {}

    def sample(self) -> None:
        truths = self.scene.truths()
        names = sorted(truths)
        xy = {n: np.array([truths[n].x, truths[n].y]) for n in names}
        where = {n: int(self.aisles.at(xy[n][0:1], xy[n][1:2])[0]) for n in names}
        meeting = set()
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                if where[a] == NO_AISLE or where[a] != where[b] or a not in self._last or b not in self._last:
                    continue
                gap = xy[b] - xy[a]
                dist = float(np.hypot(*gap))
                va, vb = xy[a] - self._last[a], xy[b] - self._last[b]
                step = MOVING / JUDGE_RATE * dist  # each closing by more than a stand-still's jitter
                if dist < MEETING_M and float(va @ gap) > step and float(vb @ -gap) > step:
                    meeting.add((a, b))
        self.head_on += len(meeting - self._meeting)
        self._meeting = meeting
        self._last = xy


class Death:
    """Robot ``name`` dies once it has inspected ``share`` of its patrol's pots: its link closes
    (its liveliness token with it) and its soft stop holds it where it is. On the sim's thread."""

    def __init__(self, fleet, name: str, share: float):
        self.fleet, self.name, self.share, self.at_s = fleet, name, share, None

    def check(self) -> None:
        service = self.fleet.services[self.name]
        run = service.run
        if self.at_s is not None or run is None:
            return
        done = sum(p["status"] == "inspected" for p in run.report.pots.values())
        if done >= self.share * len(run.tree.mission.pots):
            self.fleet.leave(self.name)
            service.estop(True)
            self.at_s = round(service.now, 1)


def _step_fleet(fleet, judge: FleetJudge, stop: threading.Event, death: Death | None) -> None:
    """``mission.jobs.fleet_sim.run_fleet`` with the judge's samples on the robots' clock."""
    clock = next(iter(fleet.services.values())).robot.scheduler.clock
    due = clock.now()
    try:
        while not stop.is_set():
            fleet.step()
            if clock.now() >= due:
                judge.sample()
                if death is not None:
                    death.check()
                due += 1.0 / JUDGE_RATE
    finally:
        fleet.close()


def fleet_run(world: World, robots: int, config: LupinConfig, kill: str | None = None) -> dict:
    """One fleet patrol of every pot of ``world`` with ``robots`` robots (robot ``kill`` dying
    ``KILL_AT`` of the way); its figures. Once per process for each."""
    key = (world.name, robots, kill)
    if key not in _RUNS:
        _RUNS[key] = _fleet_run(world, robots, config, kill)
    return _RUNS[key]


def _fleet_run(world: World, robots: int, config: LupinConfig, kill: str | None) -> dict:
    names = [f"r{k}" for k in range(1, robots + 1)]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        make_fleet(tmp / "certs", names, [])
        endpoint = free_endpoint("tls")
        router = open_router(endpoint, member_files(tmp / "certs", "router"), read_members(tmp / "certs"))
        t0 = time.perf_counter()
        fleet = start_fleet_sim(world, with_overrides(config, {"sim": {"realtime": False}}),
                                names, tmp / "runs", time.perf_counter)
        fleet.join(endpoint, lambda name: member_files(tmp / "certs", name), None)
        judge, contacts, stop = FleetJudge(fleet.scene, world), robot_contact_log(fleet.scene), threading.Event()
        death = Death(fleet, kill, KILL_AT) if kill else None
        stepper = threading.Thread(target=_step_fleet, args=(fleet, judge, stop, death), daemon=True)
        stepper.start()
        try:
            first = world.spawn_poses[0]
            inputs = Inputs(mission_from_world(world), {r: d for r, d in world_docks(world).items() if r in names},
                            plan_of_world(world, (first.x, first.y, first.yaw), config.nav.costmap.resolution), "plan")
            summary = dispatch(inputs, endpoint, member_files(tmp / "certs", "dispatcher"), names, tmp / "out", config,
                               lambda line: None, DEADLINE_S)
            wall = time.perf_counter() - t0
            reports = [json.loads(p.read_text()) for p in sorted((tmp / "out").glob("r*/report*.json"))]
        finally:
            stop.set()
            stepper.join(120)
            router.close()
        doc = {"pots": [p for r in reports for p in r["pots"]]}
        waits = {r: _aisle_wait([json.loads((tmp / "out" / f).read_text()) for f in v["reports"]])
                 for r, v in summary["robots"].items()}
        return {"robots": robots, "complete": summary["complete"], "makespan_s": summary["makespan_s"],
                "pots": len(world.pots), "pots_inspected": summary["pots"]["inspected"],
                "pots_right": correct_pots(world, doc), "robot_contacts": len(contacts.onsets), "head_on": judge.head_on,
                "aisle_wait_s": waits, "assigned": {r: len(v["assigned"]) for r, v in summary["robots"].items()},
                "handed_over": sum(len(h["pots"]) for h in summary["handovers"]),
                "killed": kill, "killed_at_s": death.at_s if death else None,
                "wall_s": round(wall, 1), "peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)}


def _aisle_wait(reports: list[dict]) -> float | None:
    """Robot seconds a robot's patrols waited for aisle locks, when the reports say."""
    waits = [r["aisles"]["wait_s"] for r in reports if isinstance(r.get("aisles"), dict) and "wait_s" in r["aisles"]]
    return round(float(sum(waits)), 1) if waits else None


def fleet_sample(world: World, config: LupinConfig) -> Sample:
    runs = [fleet_run(world, n, config) for n in ROBOTS]
    one = runs[0]["makespan_s"]
    for r in runs:
        r["makespan_share"] = round(r["makespan_s"] / one, 3) if one else None
    return Sample([r["wall_s"] * 1000.0 for r in runs], {"world": world.name, "runs": runs})


def greenhouse(size: tuple[int, int, int, int]) -> World:
    """The generated greenhouse of ``size`` (rows, pots per row, seed, bays) with a dock per robot."""
    rows, per_row, seed, bays = size
    return generate_world(rows, per_row, seed, bays=bays, robots=max(ROBOTS))


def handover_sample(world: World, config: LupinConfig) -> Sample:
    calm = fleet_run(world, max(ROBOTS), config)
    hit = fleet_run(world, max(ROBOTS), config, kill=KILLED)
    share = round(hit["makespan_s"] / calm["makespan_s"], 3) if calm["makespan_s"] else None
    return Sample([hit["wall_s"] * 1000.0], {"world": world.name, **hit, "makespan_vs_undisturbed": share,
                                             "undisturbed_makespan_s": calm["makespan_s"],
                                             "undisturbed_pots_right": calm["pots_right"]})


@benchmark("fleet.patrol")
def large(config: LupinConfig) -> Sample:
    return fleet_sample(greenhouse(LARGE), config)


@benchmark("fleet.patrol_small")
def small(config: LupinConfig) -> Sample:
    return fleet_sample(greenhouse(SMALL), config)


@benchmark("fleet.handover")
def handover_large(config: LupinConfig) -> Sample:
    return handover_sample(greenhouse(LARGE), config)


@benchmark("fleet.handover_small")
def handover_small(config: LupinConfig) -> Sample:
    return handover_sample(greenhouse(SMALL), config)
