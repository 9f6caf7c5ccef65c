"""Directed re-scouting: the pots with a pest in the last N patrols plus their neighbours within
R metres, in the shortest order, written as a mission that loads like any other."""
from __future__ import annotations

from datetime import timedelta

import numpy as np

from lupin.cli import main
from mission.history.rescout import rescout, select_pots
from mission.patrol.mission_file import load_mission
from mission.patrol.visit_order import straight_lines

from .conftest import T0, add_patrol, obs

# a 4 x 3 lattice of pots 1 m apart: P<row><col>
GRID = {f"P{r}{c}": (float(c), float(r)) for r in range(3) for c in range(4)}


def patrol(h, pests=(), when=T0, mission="m"):
    rows = [obs(p, bug=p in pests, x=x, y=y, facing=-1.5708, tag=int(p[1:])) for p, (x, y) in GRID.items()]
    return add_patrol(h, rows, mission=mission, started=when)


def test_pests_in_the_last_n_patrols_and_their_neighbours(sqlite_history):
    h = sqlite_history
    patrol(h, pests={"P00"}, when=T0)  # older than the last 2: not chosen
    patrol(h, pests={"P11"}, when=T0 + timedelta(hours=6))
    patrol(h, pests=(), when=T0 + timedelta(hours=12))
    found, around = select_pots(h.pest_map(2), radius=1.0)
    assert [p.pot_id for p in found] == ["P11"]
    assert sorted(p.pot_id for p in around) == ["P01", "P10", "P12", "P21"]  # 1 m: not the diagonals (1.41 m)
    found, around = select_pots(h.pest_map(2), radius=1.5)
    assert len(around) == 8  # the diagonals too
    assert select_pots(h.pest_map(2), radius=0.0)[1] == []
    found, _ = select_pots(h.pest_map(3), radius=0.0)
    assert sorted(p.pot_id for p in found) == ["P00", "P11"]


def test_the_mission_is_in_the_shortest_order_from_home(sqlite_history):
    h = sqlite_history
    patrol(h, pests={"P03", "P20"}, when=T0)
    plan = rescout(h.pest_map(1), radius=1.0)
    ids = [p.id for p in plan.mission.pots]
    assert sorted(ids) == sorted(["P03", "P02", "P13", "P20", "P10", "P21"])
    assert set(plan.pests) == {"P03", "P20"} and plan.mission.order == "shortest"
    assert plan.mission.name == "m-rescout"

    def tour(order):  # the approach poses from home and back, as the patrol drives them
        m = plan.mission
        pts = np.array([[m.home.x, m.home.y], *[m.approach(m.pots[ids.index(i)])[:2] for i in order],
                        [m.home.x, m.home.y]])
        return straight_lines(pts)[np.arange(len(pts) - 1), np.arange(1, len(pts))].sum()

    # the two clusters are visited one after the other, never interleaved
    cluster = {"P03": 0, "P02": 0, "P13": 0, "P20": 1, "P10": 1, "P21": 1}
    assert sum(cluster[a] != cluster[b] for a, b in zip(ids, ids[1:])) == 1
    assert tour(ids) <= tour(sorted(ids)) + 1e-9


def test_no_pest_no_mission(sqlite_history):
    patrol(sqlite_history)
    assert rescout(sqlite_history.pest_map(3), radius=2.0) is None


def test_the_command_writes_a_mission_that_patrols_like_any_other(tmp_path, capsys, sqlite_history):
    patrol(sqlite_history, pests={"P12"})
    db = str(sqlite_history.target.path)
    out = tmp_path / "rescout.yaml"
    assert main(["mission", "rescout", "--history", db, "--last", "2", "--radius", "1", "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert "1 with a pest" in said and "P12" in said and "4 within 1 m (P02, P11, P13, P22)" in said
    m = load_mission(out)  # the strict reader every patrol uses
    assert {p.id for p in m.pots} == {"P12", "P02", "P11", "P13", "P22"}
    p12 = next(p for p in m.pots if p.id == "P12")
    assert (p12.x, p12.y, p12.tag) == (2.0, 1.0, 12) and abs(p12.facing + 1.5708) < 1e-9


def test_the_command_with_nothing_to_rescout_or_bad_input(tmp_path, capsys, sqlite_history):
    patrol(sqlite_history)
    db = str(sqlite_history.target.path)
    assert main(["mission", "rescout", "--history", db, "-o", str(tmp_path / "r.yaml")]) == 1
    assert "nothing to re-scout" in capsys.readouterr().err and not (tmp_path / "r.yaml").exists()
    for args, says in ((["--radius", "-1"], "--radius"), (["--last", "0"], "--last"),
                       (["--mission", "nope"], "--mission nope"),
                       (["--history", str(tmp_path / "absent.db")], "no history database")):
        argv = ["mission", "rescout", *(["--history", db] if "--history" not in args else []), *args]
        assert main(argv) == 2, args
        err = capsys.readouterr().err
        assert says in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
