"""`lupin fleet patrol` on real robots through a real TLS router: each robot a sim service of
the same generated 3 x 4 greenhouse started at its own dock (the world's ``spawns``), running as
fast as the machine allows, its link joined to the router under its certificate; the dispatcher
as ``dispatcher``. Two robots split the pots and inspect all; a robot killed mid-patrol hands
its pots over; a fleet e-stop stops both, hands nothing over, and ``resume`` restarts both; one
robot alone inspects what ``lupin patrol`` inspects; bad input is exit 2 with one line."""
from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import pytest

from fleet.certs import member_files
from fleet.fleet_patrol import fleet_patrol, read_inputs
from lupin.cli import main
from mission.jobs.serve import run_service
from mission.jobs.sim_serve import start_sim_service
from mission.link.fleet_link import FleetLink
from mission.link.server import LinkServer
from mission.patrol.mission_file import dump_mission, mission_from_world
from mission.runtime.config import LupinConfig, with_overrides
from sim.generate import generate_world
from sim.world import dump_world
from tests.fleet.conftest import wait_for

SEED = 1


@pytest.fixture(scope="module")
def greenhouse(tmp_path_factory) -> tuple[Path, Path]:
    """The 3 x 4 greenhouse with two docks, and the mission of its 12 pots (first dock's frame)."""
    d = tmp_path_factory.mktemp("greenhouse")
    world = generate_world(3, 4, SEED, robots=2)
    (d / "world.yaml").write_text(dump_world(world))
    (d / "mission.yaml").write_text(dump_mission(mission_from_world(world)))
    return d / "world.yaml", d / "mission.yaml"


class SimRobot:
    """Robot ``rK``: a sim service of the world started at its K-th spawn, its link on the router."""

    def __init__(self, name: str, world_path: Path, endpoint: str, certs: Path, runs: Path):
        from sim.world import load_world

        world = load_world(world_path)
        k = int(name[1:]) - 1
        mine = world.model_copy(update={"spawn": world.spawns[k], "spawns": []})
        config = with_overrides(LupinConfig(), {"sim": {"realtime": False, "seed": SEED},
                                                "link": {"robot": name, "command_timeout": 8.0}})
        self.service = start_sim_service(mine, config, runs, time.perf_counter)
        self.server = LinkServer(self.service, config.link, None, connect=endpoint, tls=member_files(certs, name))
        self._stop = threading.Event()
        self._thread = threading.Thread(target=run_service, args=(self.service, self._stop, self.server.close), daemon=True)
        self._thread.start()

    def inspected(self) -> int:
        run = self.service.run
        return 0 if run is None else sum(p["status"] == "inspected" for p in run.report.pots.values())

    def close(self) -> None:
        self._stop.set()
        self._thread.join(60)


@pytest.fixture
def robots(request, router, certs, greenhouse, tmp_path):
    names = getattr(request, "param", ("r1", "r2"))
    got = {n: SimRobot(n, greenhouse[0], router, certs, tmp_path / "runs" / n) for n in names}
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
    assert wait_for(lambda: all(r.server for r in robots.values()), 5)
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
    assert (out / "fleet.png").stat().st_size > 0


@pytest.mark.slow
def test_a_robot_killed_mid_patrol_hands_its_pots_over_and_every_pot_is_inspected(router, certs, greenhouse, robots,
                                                                                  tmp_path):
    d = Dispatch(router, certs, greenhouse, tmp_path / "fleet")
    assert wait_for(lambda: robots["r2"].inspected() >= 2, 300), d.lines
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
def test_a_fleet_estop_stops_every_robot_hands_nothing_over_and_resume_restarts_them_all(router, certs, greenhouse,
                                                                                      robots, tmp_path):
    config = with_overrides(LupinConfig(), {"fleet": {"handover_after": 2.0}})
    d = Dispatch(router, certs, greenhouse, tmp_path / "fleet", config)
    assert wait_for(lambda: all(r.inspected() >= 1 for r in robots.values()), 300), d.lines
    console = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=10.0)
    try:
        assert console.stop_fleet() == ["r1", "r2"]
        held = {n: r.service.now for n, r in robots.items()}
        assert wait_for(lambda: all(r.service.now - held[n] > 4 * 2.0 for n, r in robots.items()), 60)
        assert all(r.service.run.tree.holds.latched and not r.service.robot.base.last_duties.any() for r in robots.values())
        done = {n: r.inspected() for n, r in robots.items()}
        assert wait_for(lambda: all(r.service.now - held[n] > 8 * 2.0 for n, r in robots.items()), 60)
        assert {n: r.inspected() for n, r in robots.items()} == done  # nobody moved on while stopped
        assert console.resume_fleet() == {"r1": None, "r2": None}
    finally:
        console.close()
    summary = d.wait()
    assert summary["complete"] and summary["handovers"] == []  # two robots stopped: nobody to take pots
    assert all(v["handover_reason"] is None and v["outcome"] == "completed" for v in summary["robots"].values())


@pytest.mark.slow
@pytest.mark.parametrize("robots", [("r1",)], indirect=True)
def test_one_robot_alone_inspects_the_pots_lupin_patrol_inspects(router, certs, greenhouse, robots, tmp_path):
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
