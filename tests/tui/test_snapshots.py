"""Snapshots of the console's main states (pytest-textual-snapshot; regenerate with
``pytest tests/tui --snapshot-update`` after a deliberate change, and look at the SVGs)."""
from __future__ import annotations

from tests.tui.fakes import Recorder, estopped_view, idle_view, patrolling_view
from tui.app import make_app

SIZE = (160, 48)


def test_idle(snap_compare):
    assert snap_compare(make_app(idle_view, Recorder()), terminal_size=SIZE)


def test_patrolling(snap_compare):
    assert snap_compare(make_app(patrolling_view, Recorder()), terminal_size=SIZE)


def test_estopped(snap_compare):
    assert snap_compare(make_app(estopped_view, Recorder()), terminal_size=SIZE)
