"""The console under Pilot: every key binding sends exactly its command, the clear-map question,
refusals shown; and the map renderer draws things where they are."""
from __future__ import annotations

import asyncio

import numpy as np
import pytest

from tests.tui.fakes import Recorder, estopped_view, idle_view, patrolling_view
from tui.app import ARM_PRESETS, make_app
from tui.widgets.camera_panel import CameraPanel
from tui.widgets.log_panel import LogPanel
from tui.widgets.map_panel import Canvas, render_map

SIZE = (160, 50)


def run(view, keys, refuse=None):
    """Press ``keys`` in a console showing ``view``; returns (recorder, app) after every
    command has gone out."""
    rec = Recorder(refuse)

    async def go():
        app = make_app(lambda: view, rec)
        async with app.run_test(size=SIZE) as pilot:
            for k in keys:
                if k == "wait":
                    await pilot.pause(0.35)  # a few redraws
                else:
                    await pilot.press(k)
            await pilot.pause()
            await app.workers.wait_for_complete()
            await pilot.pause()
            return app, app.query_one(LogPanel).lines[:], str(app.query_one(CameraPanel).render())

    app, log, camera = asyncio.run(go())
    return rec, log, camera


@pytest.mark.parametrize("key, command, args", [
    ("up", "teleop", {"vx": 0.2, "vy": 0.0, "wz": 0.0}),
    ("down", "teleop", {"vx": -0.2, "vy": 0.0, "wz": 0.0}),
    ("left", "teleop", {"vx": 0.0, "vy": 0.2, "wz": 0.0}),  # strafe: the mecanum base
    ("right", "teleop", {"vx": 0.0, "vy": -0.2, "wz": 0.0}),
    ("q", "teleop", {"vx": 0.0, "vy": 0.0, "wz": 0.5}),
    ("e", "teleop", {"vx": 0.0, "vy": 0.0, "wz": -0.5}),
    ("r", "resume", {}),
    ("m", "mission_start", {}),
    ("p", "pause", {}),
    ("o", "gripper", {"action": "open"}),
    ("g", "gripper", {"action": "close"}),
    *[(str(i + 1), "arm_preset", {"name": name}) for i, name in enumerate(ARM_PRESETS)],
])
def test_each_key_sends_its_command(key, command, args):
    rec, _, _ = run(patrolling_view(), [key])
    assert rec.sent == [(command, args)]


def test_holding_a_drive_key_sends_a_twist_per_repeat():
    rec, _, _ = run(patrolling_view(), ["left"] * 5)
    assert rec.sent == [("teleop", {"vx": 0.0, "vy": 0.2, "wz": 0.0})] * 5


def test_space_engages_the_soft_estop_and_releases_it_when_engaged():
    assert run(patrolling_view(), ["space"])[0].sent == [("estop", {"engaged": True})]
    assert run(estopped_view(), ["space"])[0].sent == [("estop", {"engaged": False})]


def test_clear_map_asks_first():
    assert run(patrolling_view(), ["c", "n"])[0].sent == []
    assert run(patrolling_view(), ["c", "wait", "n"])[0].sent == []  # the screen keeps redrawing under the question
    assert run(patrolling_view(), ["c", "escape"])[0].sent == []
    assert run(patrolling_view(), ["c", "y"])[0].sent == [("clear_map", {})]


def test_a_refused_command_is_shown_with_its_reason():
    rec, log, _ = run(idle_view(), ["p"], refuse={"pause": "pause: no mission is running"})
    assert rec.sent == [("pause", {})]
    assert any("no mission is running" in line.text for line in log)


def test_snapshot_keys_fetch_and_draw_the_camera():
    rec, _, camera = run(idle_view(), ["f"])
    assert rec.snapshots == ["front"] and "front camera" in camera
    rec, _, camera = run(idle_view(), ["w"])
    assert rec.snapshots == ["wrist"] and "wrist camera" in camera


def test_the_map_draws_robot_plan_and_pots_where_they_are():
    v = patrolling_view()
    strips = render_map(v, 80, 30)
    assert len(strips) == 30 and all(strip.cell_length == 80 for strip in strips)
    cv = Canvas(v, 80, 30)

    def colour_at(x, y):
        import tui.widgets.map_panel as mp

        seen = {}
        real = mp.half_block_rows
        mp.half_block_rows = lambda rgb: (seen.setdefault("rgb", rgb), [])[1]
        try:
            render_map(v, 80, 30)
        finally:
            mp.half_block_rows = real
        c, r = cv.to_pixel(x, y)
        return tuple(int(k) for k in seen["rgb"][int(r), int(c)])

    from tui.widgets.map_panel import ANOMALY, HEADING, PLAN, POT_COLOURS, ROBOT

    assert colour_at(*v.pose[:2]) in (ROBOT, HEADING)
    assert colour_at(1.0, 1.0) == POT_COLOURS["inspected"]
    assert colour_at(2.0, 1.0) == ANOMALY  # inspected with a bug
    assert colour_at(4.0, 1.0) == POT_COLOURS["pending"]
    mid = (v.plan[1] + v.plan[2]) / 2
    assert colour_at(*mid) == PLAN


def test_the_map_of_an_empty_view_is_still_a_picture():
    strips = render_map(idle_view(), 40, 10)
    assert len(strips) == 10 and not np.isnan(Canvas(idle_view(), 40, 10).scale)
