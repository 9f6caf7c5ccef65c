"""The alerts after a patrol (mission.history.alerts) and the pest trend's bounded query."""
from __future__ import annotations

from datetime import timedelta

from mission.history import queries
from mission.history.alerts import alerts

from .conftest import T0, add_patrol, obs


def test_a_new_pest_beside_last_patrols_pest_is_spreading_one_far_away_is_only_new():
    before = [obs("A", bug=True, x=0.0), obs("B", x=0.9), obs("C", x=5.0)]
    after = [obs("A", bug=True, x=0.0), obs("B", bug=True, x=0.9), obs("C", bug=True, x=5.0)]
    got = [(a.pot, a.kind) for a in alerts(after, before)]
    assert got == [("B", "spreading"), ("C", "pest_new")]
    assert "0.9 m from A" in alerts(after, before)[0].detail
    assert [(a.pot, a.kind) for a in alerts(after, before, radius=0.5)] == [("B", "pest_new"), ("C", "pest_new")]


def test_failed_twice_in_a_row_and_moved_pots_need_a_person_failed_once_does_not():
    before = [obs("A", status="failed"), obs("B"), obs("C")]
    after = [obs("A", status="failed", anomalies=("unreachable",)), obs("B", status="failed"),
             obs("C", anomalies=("moved",), x=1.0, y=2.0)]
    got = alerts(after, before)
    assert [(a.pot, a.kind) for a in got] == [("A", "failed"), ("C", "moved")]
    assert "unreachable" in got[0].detail and "1.00, 2.00" in got[1].detail
    assert alerts(after, []) == [got[1]]  # no patrol before: nothing is new, nothing failed twice


def test_the_pest_trend_counts_pests_per_patrol_thinned_evenly_to_the_latest(sqlite_history):
    ids = [add_patrol(sqlite_history, [obs("A", bug=k % 3 == 0), obs("B", bug=k % 2 == 0)],
                      started=T0 + timedelta(hours=6 * k)) for k in range(40)]
    add_patrol(sqlite_history, [obs("A", bug=True)], mission="other", started=T0 + timedelta(days=20))
    add_patrol(sqlite_history, [obs("A", bug=True)], world="elsewhere", started=T0 + timedelta(days=9))
    with sqlite_history.reading() as c:
        latest = queries.patrol(c, ids[-1])
        every = queries.pest_trend(c, latest, days=28, points=100)
        thin = queries.pest_trend(c, latest, days=28, points=5)
        week = queries.pest_trend(c, latest, days=2, points=100)
    assert [p.id for p in every] == ids and [p.pests for p in every[:4]] == [2, 0, 1, 1]
    assert [p.id for p in thin] == [ids[0], ids[10], ids[20], ids[29], ids[39]]
    assert [p.id for p in week] == ids[-9:]
