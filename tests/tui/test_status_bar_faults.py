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
