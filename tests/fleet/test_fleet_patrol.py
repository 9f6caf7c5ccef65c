"""`lupin fleet patrol` on real robots through a real TLS router, the dispatcher as
``dispatcher``, on the generated 3 x 4 greenhouse with two docks (the world's ``spawns``), every
robot as fast as the machine allows.

Two kinds of robots: ``fleet``, those of ``lupin fleet sim`` (``mission.jobs.fleet_sim``: one
MuJoCo world, a runtime per robot in lock-step, each link joined to the router under its
certificate), and ``robots``, each robot in a sim of its own (the world started at its spawn).
The split of this greenhouse shares its middle aisle (8 pots against the south strip's 4), and
two robots of one world can block each other there even asking for the aisle locks first (the
second, let in once the first has left, may find it still on its SLAM map: a robot seen standing
is mapped, a ghost it may not clear); so the tests of the dispatcher's split, follow, hand-over
and the fleet e-stop use robots of their own sims (a killed robot is also a whole runtime gone,
which one runtime of a lock-step fleet cannot be), and the fleet sim's robot is the one that
behaves as ``lupin patrol``."""
from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from fleet.assign import in_dock_frame
from fleet.certs import member_files
from fleet.fleet_patrol import fleet_patrol, read_inputs
from lupin.cli import main
from mission.jobs.fleet_sim import run_fleet, start_fleet_sim
from mission.link.fleet_link import FleetLink
from mission.patrol.mission_file import dump_mission, mission_from_world
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world
from sim.world import dump_world
from tests.fleet.conftest import wait_for
from tests.fleet.test_fleet_sim import FleetRobot

SEED = 1


@pytest.fixture(scope="module")
def greenhouse(tmp_path_factory) -> tuple[Path, Path]:
    """The 3 x 4 greenhouse with two docks, and the mission of its 12 pots (first dock's frame)."""
    d = tmp_path_factory.mktemp("greenhouse")
    world = generate_world(3, 4, SEED, robots=2)
    (d / "world.yaml").write_text(dump_world(world))
    (d / "mission.yaml").write_text(dump_mission(mission_from_world(world)))
    return d / "world.yaml", d / "mission.yaml"


def fast(name: str = "") -> LupinConfig:
    return with_overrides(LupinConfig(), {"sim": {"realtime": False, "seed": SEED},
                                          "link": {"robot": name or "mirte", "command_timeout": 8.0}})


class SimRobot(FleetRobot):
    """Robot ``rK`` alone in a sim of the world started at its K-th spawn, its link on the router."""

    def __init__(self, name: str, world_path: Path, endpoint: str, certs: Path, runs: Path):
        from sim.world import load_world

        super().__init__(name, endpoint, certs, runs, load_world(world_path).for_robot(int(name[1:]) - 1), realtime=False)


class SharedSim:
    """``lupin fleet sim``'s robots: one world, a runtime each in lock-step, each link on the router."""

    def __init__(self, names, world_path: Path, endpoint: str, certs: Path, runs: Path):
        from sim.world import load_world

        self.fleet = start_fleet_sim(load_world(world_path), fast(), list(names), runs, time.perf_counter)
        self.fleet.join(endpoint, lambda name: member_files(certs, name), None)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=run_fleet, args=(self.fleet, self._stop), daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        self._thread.join(60)


def inspected(service) -> int:
    run = service.run
    return 0 if run is None else sum(p["status"] == "inspected" for p in run.report.pots.values())


@pytest.fixture
def fleet(request, router, certs, greenhouse, tmp_path):
    """The fleet sim's robots (``request.param``: their names, default r1, r2): name -> service."""
    sim = SharedSim(getattr(request, "param", ("r1", "r2")), greenhouse[0], router, certs, tmp_path / "runs")
    try:
        yield sim.fleet.services
    finally:
        sim.close()


@pytest.fixture
def robots(router, certs, greenhouse, tmp_path):
    """r1 and r2, each in a sim of its own."""
    got = {n: SimRobot(n, greenhouse[0], router, certs, tmp_path / "runs" / n) for n in ("r1", "r2")}
    try:
        yield got
    finally:
        for r in got.values():
            r.close()


class Dispatch:
    """``fleet_patrol`` on its own thread (the test watches and acts meanwhile)."""

    def __init__(self, router: str, certs: Path, greenhouse, out: Path, config: LupinConfig | None = None):
        self.config = config or LupinConfig()
        inputs = read_inputs(greenhouse[1], greenhouse[0], None, self.config)
        self.lines: list[str] = []
        self.summary = None
        self._thread = threading.Thread(target=self._run, args=(inputs, router, member_files(certs, "dispatcher"), out),
                                        daemon=True)
        self._thread.start()

    def _run(self, inputs, router, tls, out) -> None:
        self.summary = fleet_patrol(inputs, router, tls, None, out, self.config, self.lines.append, 600.0)

    def wait(self, timeout: float = 600.0) -> dict:
        self._thread.join(timeout)
        assert self.summary is not None, f"the fleet patrol did not end: {self.lines}"
        return self.summary


def _all_pots(greenhouse) -> list[str]:
    return [p.id for p in read_inputs(greenhouse[1], greenhouse[0], None, LupinConfig()).mission.pots]


@pytest.mark.slow
def test_two_robots_split_the_greenhouse_and_inspect_every_pot(router, certs, greenhouse, robots, tmp_path):
    out = tmp_path / "fleet"
    code = main(["fleet", "patrol", "--mission", str(greenhouse[1]), "--world", str(greenhouse[0]), "--connect", router,
                 "--certs", str(certs), "--report", str(out)])
    assert code == 0
    summary = json.loads((out / "fleet.json").read_text())
    pots = _all_pots(greenhouse)
    assigned = {r: v["assigned"] for r, v in summary["robots"].items()}
    assert set(assigned) == {"r1", "r2"} and all(assigned.values())
    assert sorted(assigned["r1"] + assigned["r2"]) == sorted(pots)  # split: every pot once
    assert summary["complete"] and summary["pots"]["not_inspected"] == [] and summary["handovers"] == []
    for r, v in summary["robots"].items():
        report = json.loads((out / v["report"]).read_text())  # the robot's own, fetched through the link
        assert report["mission"] == summary["mission"] and report["outcome"] == "completed"
        assert sorted(p["id"] for p in report["pots"]) == sorted(assigned[r])
        assert sorted(v["done"]) == sorted(assigned[r]) and 0 < v["robot_time_s"] <= summary["makespan_s"]
        # its person tracker knows the other robot's pots for pots too, each where it stands in its own map
        inputs = read_inputs(greenhouse[1], greenhouse[0], None, LupinConfig())
        mapped = np.array([(q.x, q.y) for q in (in_dock_frame(p, inputs.docks[r]) for p in inputs.mission.pots)])
        known = robots[r].service.robot.people.pots
        assert len(known) == len(mapped)
        assert np.hypot(*(known[:, None, :] - mapped[None, :, :]).transpose(2, 0, 1)).min(axis=1).max() < 0.01
    assert (out / "fleet.png").stat().st_size > 0


@pytest.mark.slow
def test_a_robot_killed_mid_patrol_hands_its_pots_over_and_every_pot_is_inspected(router, certs, greenhouse, robots,
                                                                                  tmp_path):
    d = Dispatch(router, certs, greenhouse, tmp_path / "fleet")
    assert wait_for(lambda: inspected(robots["r2"].service) >= 2, 300), d.lines
    robots["r2"].close()  # its runtime and link gone: its liveliness token goes with them
    written = json.loads(robots["r2"].service.report_path.read_text())  # its report, finished as it went
    really = {p["id"] for p in written["pots"] if p["status"] == "inspected"}
    summary = d.wait()
    r2 = summary["robots"]["r2"]
    assert r2["handover_reason"] == "liveliness" and r2["outcome"] == "lost" and r2["handed_over"]
    # its pots as its last report fetched said: what it inspected (the last pot may not have been fetched)
    assert set(r2["done"]) <= really and sorted(r2["done"] + r2["handed_over"]) == sorted(r2["assigned"])
    [given] = summary["handovers"]
    assert (given["from"], given["to"], given["why"], sorted(given["pots"])) == ("r2", "r1", "liveliness",
                                                                                sorted(r2["handed_over"]))
    assert given["at_s"] > 0
    r1 = summary["robots"]["r1"]
    assert r1["received"] == given["pots"] and set(given["pots"]) <= set(r1["done"])
    assert len(r1["reports"]) == 2  # its own patrol, then a further one of r2's pots
    assert summary["complete"] and sorted(r1["done"] + r2["done"]) == sorted(_all_pots(greenhouse))


@pytest.mark.slow
def test_a_robot_stopped_longer_than_handover_after_hands_its_pots_over(router, certs, greenhouse, robots, tmp_path):
    config = with_overrides(LupinConfig(), {"fleet": {"handover_after": 2.0}})
    d = Dispatch(router, certs, greenhouse, tmp_path / "fleet", config)
    assert wait_for(lambda: inspected(robots["r2"].service) >= 1, 300), d.lines
    robots["r2"].service.estop(True)  # as its stop key does: held, while r1 goes on
    summary = d.wait()
    r2, r1 = summary["robots"]["r2"], summary["robots"]["r1"]
    assert r2["handover_reason"] == "estop" and r2["outcome"] == "aborted" and r2["handed_over"]
    assert [(h["from"], h["to"], h["why"]) for h in summary["handovers"]] == [("r2", "r1", "estop")]
    assert r1["received"] == summary["handovers"][0]["pots"] and set(r2["handed_over"]) <= set(r1["done"])
    assert summary["complete"]


@pytest.mark.slow
def test_a_robot_whose_battery_runs_low_goes_home_and_hands_its_pots_over(router, certs, greenhouse, robots, tmp_path):
    d = Dispatch(router, certs, greenhouse, tmp_path / "fleet")
    r2 = robots["r2"].service
    assert wait_for(lambda: r2.run is not None and r2.run.tree.mission.pots, 300), d.lines
    r2.robot.power.monitor.forced_voltage = 10.5  # below 11.1 V: power low 20 s of its clock later
    summary = d.wait()
    got, r1 = summary["robots"]["r2"], summary["robots"]["r1"]
    assert got["handover_reason"] == "battery_low" and got["outcome"] == "battery_low" and got["handed_over"]
    assert sorted(got["done"] + got["handed_over"]) == sorted(got["assigned"])
    assert [(h["from"], h["to"], h["why"]) for h in summary["handovers"]] == [("r2", "r1", "battery_low")]
    assert sorted(r1["received"]) == sorted(got["handed_over"]) and set(got["handed_over"]) <= set(r1["done"])
    assert summary["complete"]


@pytest.mark.slow
def test_a_fleet_estop_stops_every_robot_hands_nothing_over_and_resume_restarts_them_all(router, certs, greenhouse,
                                                                                      robots, tmp_path):
    fleet = {n: r.service for n, r in robots.items()}
    after = 10.0  # robot s; the two sims' clocks run apart in wall time, so not shorter than the telemetry's lag
    config = with_overrides(LupinConfig(), {"fleet": {"handover_after": after}})
    d = Dispatch(router, certs, greenhouse, tmp_path / "fleet", config)
    assert wait_for(lambda: all(inspected(s) >= 1 for s in fleet.values()), 300), d.lines
    console = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=10.0)
    try:
        assert console.stop_fleet() == ["r1", "r2"]
        held = {n: s.now for n, s in fleet.items()}
        assert wait_for(lambda: all(s.now - held[n] > 2 * after for n, s in fleet.items()), 60)
        assert all(s.run.tree.holds.latched and not s.robot.base.last_duties.any() for s in fleet.values())
        done = {n: inspected(s) for n, s in fleet.items()}
        assert wait_for(lambda: all(s.now - held[n] > 3 * after for n, s in fleet.items()), 60)
        assert {n: inspected(s) for n, s in fleet.items()} == done  # nobody moved on while stopped
        assert console.resume_fleet() == {"r1": None, "r2": None}
    finally:
        console.close()
    summary = d.wait()
    assert summary["complete"] and summary["handovers"] == []  # two robots stopped: nobody to take pots
    assert all(v["handover_reason"] is None and v["outcome"] == "completed" for v in summary["robots"].values())


@pytest.mark.slow
@pytest.mark.parametrize("fleet", [("r1",)], indirect=True)
def test_one_robot_alone_inspects_the_pots_lupin_patrol_inspects(router, certs, greenhouse, fleet, tmp_path):
    out = tmp_path / "fleet"
    assert main(["fleet", "patrol", "--mission", str(greenhouse[1]), "--world", str(greenhouse[0]), "--connect", router,
                 "--certs", str(certs), "--report", str(out), "--robots", "r1"]) == 0
    fleet = json.loads((out / "r1" / "report.json").read_text())
    alone = tmp_path / "alone" / "report.json"
    assert main(["patrol", "--world", str(greenhouse[0]), "--mission", str(greenhouse[1]), "--seed", str(SEED),
                 "--report", str(alone)]) == 0
    patrol = json.loads(alone.read_text())
    assert fleet["outcome"] == patrol["outcome"] == "completed"
    assert {p["id"]: p["status"] for p in fleet["pots"]} == {p["id"]: p["status"] for p in patrol["pots"]}
    assert {p["id"]: p.get("tag_read") for p in fleet["pots"]} == {p["id"]: p.get("tag_read") for p in patrol["pots"]}


def test_bad_robots_a_bad_mission_and_no_robot_up_are_exit_2_with_one_line(router, certs, greenhouse, tmp_path, capsys):
    base = ["fleet", "patrol", "--world", str(greenhouse[0]), "--connect", router, "--certs", str(certs),
            "--report", str(tmp_path / "out")]
    bad_mission = tmp_path / "bad.yaml"
    bad_mission.write_text("name: x\npots: [{id: P1, x: 1.0}]\n")
    cases = [
        (["--mission", str(greenhouse[1]), "--robots", "r1,,r!"], "--robots r1,,r!: expected robot names"),
        (["--mission", str(bad_mission)], str(bad_mission)),
        (["--mission", str(greenhouse[1])], "no robot is up on the router"),
        (["--mission", str(greenhouse[1]), "--robots", "r2"], "--robots: r2 not up on the router (up: none)"),
    ]
    for extra, words in cases:
        assert main(base + extra) == 2, extra
        err = capsys.readouterr().err
        assert words in err and "Traceback" not in err, (extra, err)
    assert not (tmp_path / "out").exists()
