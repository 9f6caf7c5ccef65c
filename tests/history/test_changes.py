"""What changed between two patrols: each kind on a hand-built pair, nothing when nothing changed,
and ``lupin``'s ``changes`` query over a hand-built history (the last two patrols of a mission)."""
from __future__ import annotations

from datetime import timedelta

from mission.history.changes import pot_changes

from .conftest import T0, add_patrol, obs


def kinds(before, after):
    return [(c.kind, c.before, c.after) for c in pot_changes(before, after)]


def test_nothing_changed_gives_nothing():
    assert kinds(obs("P1", bug=True, blooms=3), obs("P1", bug=True, blooms=3)) == []
    assert kinds(obs("P1", status="failed"), obs("P1", status="failed")) == []  # still failing is not news


def test_a_new_pest_and_a_cleared_one():
    assert kinds(obs("P1", bug=False), obs("P1", bug=True)) == [("pest_new", False, True)]
    assert kinds(obs("P1", status="failed"), obs("P1", bug=True)) == [("pest_new", None, True)]
    assert kinds(obs("P1", bug=True), obs("P1", bug=False)) == [("pest_cleared", True, False)]


def test_an_unjudged_pot_clears_nothing_and_changes_no_colour():
    """Failed now: the pest may still be there; only 'failed' is news."""
    assert kinds(obs("P1", bug=True, color="red"), obs("P1", status="failed", anomalies=("unreachable",))) == [
        ("failed", "inspected", "failed")]


def test_colour_and_bloom_count():
    assert kinds(obs("P1", color="red", blooms=1), obs("P1", color="white", blooms=1)) == [("color", "red", "white")]
    assert kinds(obs("P1", blooms=1), obs("P1", blooms=3)) == [("blooms", 1, 3)]
    assert kinds(obs("P1", color="red", blooms=1), obs("P1", color="none", blooms=0)) == [
        ("color", "red", "none"), ("blooms", 1, 0)]


def test_newly_failed_says_why():
    [c] = pot_changes(obs("P1"), obs("P1", status="failed", anomalies=("unreachable",)))
    assert c.kind == "failed" and "unreachable" in c.detail


def test_changes_between_the_last_two_patrols_of_a_mission(sqlite_history):
    h = sqlite_history
    add_patrol(h, [obs("P1", bug=True), obs("P2"), obs("P3")], started=T0 - timedelta(days=1))  # too old
    first = add_patrol(h, [obs("P1"), obs("P2", blooms=2), obs("P3"), obs("P4")], started=T0)
    add_patrol(h, [obs("P1", bug=True)], mission="other", started=T0 + timedelta(hours=1))  # another mission
    second = add_patrol(h, [obs("P1", bug=True), obs("P2", blooms=3), obs("P3", status="failed"), obs("P4")],
                        started=T0 + timedelta(hours=2))
    cs = h.changes("m")
    assert (cs.before.id, cs.after.id) == (first, second)
    assert [(c.pot, c.kind) for c in cs.changes] == [("P1", "pest_new"), ("P2", "blooms"), ("P3", "failed")]
    assert h.changes().after.mission == "m"  # the latest patrol's mission by default
    assert h.changes("other").before is None  # one patrol: nothing to compare


def test_no_change_between_two_identical_patrols(sqlite_history):
    rows = [obs("P1", bug=True), obs("P2", color="white", blooms=2)]
    add_patrol(sqlite_history, rows, started=T0)
    add_patrol(sqlite_history, rows, started=T0 + timedelta(hours=6))
    cs = sqlite_history.changes()
    assert cs.before is not None and cs.changes == ()


def test_an_empty_history_has_no_changes(sqlite_history):
    cs = sqlite_history.changes()
    assert cs.after is None and cs.before is None and cs.changes == ()
