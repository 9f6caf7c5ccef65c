"""One greenhouse's data stays its own (spec/history.md, issue 29): sim patrols of one world and
the robot's patrols (world null) of a mission with the same name are different greenhouses, so
``changes``, ``pests``, a pot's timeline, ``rescout``, the console's answers and a starting
patrol's "previous patrol" compare only within one, whichever robot made them, unless ``--all``."""
from __future__ import annotations

import json
from datetime import timedelta

from lupin.cli import main
from mission.history.answers import answer

from .conftest import T0, add_patrol, obs

H = timedelta(hours=6)


def three_greenhouses(h) -> dict[str, int]:
    """The robots' real patrols of "bay", a sim test patrol of "bay" in between, then another real one."""
    return {
        "robot1": add_patrol(h, [obs("P01", bug=False, x=0), obs("P02", x=1)], mission="bay", robot="mirte",
                             started=T0, world=None),
        "sim": add_patrol(h, [obs("P01", bug=True, x=0), obs("P02", color="white", x=1)], mission="bay",
                          robot="mirte", started=T0 + H, world="greenhouse"),
        "robot2": add_patrol(h, [obs("P01", bug=False, x=0), obs("P02", blooms=3, x=1)], mission="bay", robot="fred",
                             started=T0 + 2 * H, world=None),
    }


def test_changes_compare_with_the_same_greenhouse_whichever_robot(sqlite_history):
    h = sqlite_history
    ids = three_greenhouses(h)
    cs = h.changes("bay")
    assert (cs.after.id, cs.before.id) == (ids["robot2"], ids["robot1"])  # fred's patrol against mirte's, not the sim's
    assert [(c.pot, c.kind) for c in cs.changes] == [("P02", "blooms")]
    every = h.changes("bay", every=True)
    assert every.before.id == ids["sim"]
    assert [(c.pot, c.kind) for c in every.changes] == [("P01", "pest_cleared"), ("P02", "color"), ("P02", "blooms")]


def test_pests_timeline_and_the_previous_patrol_stay_in_one_greenhouse(sqlite_history):
    h = sqlite_history
    ids = three_greenhouses(h)
    pm = h.pest_map(10, "bay")
    assert [p.id for p in pm.patrols] == [ids["robot2"], ids["robot1"]]
    assert all(p.pests == 0 for p in pm.pots)  # the sim's pest is not the robot's greenhouse's
    assert {p.pot_id: p.pests for p in h.pest_map(10, "bay", every=True).pots} == {"P01": 1, "P02": 0}
    assert [e.patrol for e in h.pot_timeline("P01")] == [ids["robot1"], ids["robot2"]]
    assert [e.world for e in h.pot_timeline("P01", every=True)] == [None, "greenhouse", None]
    previous, rows = h.previous_observations("bay", "greenhouse")  # a sim patrol starting in that world
    assert previous.id == ids["sim"] and rows["P01"].bug is True
    assert h.previous_observations("bay", None)[0].id == ids["robot2"]
    assert h.previous_observations("bay", "other-world") == (None, {})
    assert [e["patrol"] for e in answer(h, "pot", pot="P01")["timeline"]] == [ids["robot1"], ids["robot2"]]
    assert answer(h, "changes", every=True)["before"]["id"] == ids["sim"]


def test_the_cli_scopes_unless_all(sqlite_history, tmp_path, capsys):
    h = sqlite_history
    ids = three_greenhouses(h)
    db = str(h.target.path)
    assert main(["history", "changes", "--history", db, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["before"]["id"] == ids["robot1"]
    assert main(["history", "changes", "--history", db, "--json", "--all"]) == 0
    assert json.loads(capsys.readouterr().out)["before"]["id"] == ids["sim"]
    assert main(["history", "pests", "--history", db, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["patrols"] == [ids["robot2"], ids["robot1"]]
    assert main(["history", "pot", "P01", "--history", db, "--all"]) == 0
    assert "3 observation(s)" in capsys.readouterr().out
    # rescout: no pest in the robot's greenhouse; the sim's pest only with --all
    assert main(["mission", "rescout", "--history", db, "--last", "3", "--radius", "0.5"]) == 1
    capsys.readouterr()
    assert main(["mission", "rescout", "--history", db, "--last", "3", "--radius", "0.5", "--all",
                 "-o", str(tmp_path / "r.yaml")]) == 0
    assert "P01" in (tmp_path / "r.yaml").read_text()
