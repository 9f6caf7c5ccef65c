"""The status bar's safety chips: a blind or stale lidar and a robot running without its
collision monitor are red alarms, and nothing shows while all is well."""
from __future__ import annotations

from mission.link.view import RobotView
from tests.tui.fakes import idle_view
from tui.widgets.status_bar import ALARM, status_chips, status_text


def chip(v: RobotView, text: str):
    return next((c for c in status_chips(v) if c.plain.strip() == text), None)


def test_a_blind_lidar_is_a_red_chip():
    v = idle_view()
    assert "lidar" not in status_text(v).plain
    v.monitor_fault = "lidar_blind"
    c = chip(v, "lidar blind")
    assert c is not None and c.style == ALARM


def test_the_monitor_turned_off_is_a_red_chip():
    v = idle_view()
    assert "COLLISION MONITOR OFF" not in status_text(v).plain
    v.monitor_enabled = False
    c = chip(v, "COLLISION MONITOR OFF")
    assert c is not None and c.style == ALARM


def test_the_patrols_charge_its_charge_at_the_dock_and_why_it_heads_home_are_chips():
    v = idle_view()
    assert "charge" not in status_text(v).plain and "heading home" not in status_text(v).plain
    v.charge, v.charge_at_dock = 0.42, 0.19
    assert chip(v, "charge 42%, 19% at the dock") is not None
    v.heading_home = "before P102: charge 18%"
    c = chip(v, "heading home: before P102: charge 18%")
    assert c is not None and c.style == "bold black on yellow"
