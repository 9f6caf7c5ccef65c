"""The fleet console (``tui.fleet_app``) over a real ``FleetLink`` on a real TLS router: robots are
listed by key, 1-9 switch the robot the commands go to, F1-F6 are the arm presets, ``E`` stops
every robot. The robots are sessions under their own certificates that answer like a runtime's
link (tests/fleet/test_fleet_sim.py has the real runtimes)."""
from __future__ import annotations

import asyncio
import json
import time

from mission.link.fleet_link import FleetLink
from fleet.certs import member_files
from tests.fleet.conftest import certs, member, router, wait_for  # noqa: F401  (fixtures)
from tui.fleet_app import FleetConsoleApp
from tui.keys import ARM_PRESETS
from tui.widgets.status_bar import status_text


def test_keys_pick_the_robot_send_it_commands_and_capital_e_stops_the_fleet(router, certs):
    heard: list[tuple[str, str, dict]] = []
    robots, keep = [member(router, certs, n) for n in ("r1", "r2")], []
    for name, s in zip(("r1", "r2"), robots):
        def answer(q, name=name):
            heard.append((name, str(q.key_expr).rsplit("/", 1)[-1], json.loads(q.payload.to_bytes() or b"{}")))
            q.reply(q.key_expr, json.dumps({"ok": True, "robot": name}).encode())
        keep += [s.declare_queryable(f"lupin/{name}/cmd/*", answer), s.declare_queryable(f"lupin/{name}/stop", answer),
                 s.declare_queryable("lupin/fleet/stop", answer), s.liveliness().declare_token(f"lupin/{name}/alive")]
    fleet = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"))
    try:
        assert wait_for(lambda: fleet.robots() == ["r1", "r2"])

        async def go():
            app = FleetConsoleApp(fleet)
            async with app.run_test(size=(160, 48)) as pilot:
                await pilot.pause()
                assert "1 r1  2 r2" in status_text(app.view).plain and app.view.robot == "r1"
                footer = app.main.query_one("#keys").text.plain
                assert "f1 f2 f3 f4 f5 f6 arm" in footer and "123456789 robot" in footer and "E FLEET E-STOP" in footer
                await pilot.press("f1")
                await app.workers.wait_for_complete()
                await pilot.press("2")
                await pilot.pause()
                assert app.view.robot == "r2"
                await pilot.press("space")
                await app.workers.wait_for_complete()
                await pilot.press("9")  # no ninth robot: nothing changes
                await pilot.press("E")
                await app.workers.wait_for_complete()
                await pilot.pause()
                assert app.view.robot == "r2"

        asyncio.run(go())
        assert ("r1", "arm_preset", {"name": ARM_PRESETS[0], "token": ""}) in heard
        assert ("r2", "estop", {"engaged": True, "token": ""}) in heard
        assert sorted(n for n, what, _ in heard if what == "stop") == ["r1", "r2"]
        assert not any(n == "r2" and what == "arm_preset" for n, what, _ in heard)
        assert keep
    finally:
        fleet.close()
        for s in robots:
            s.close()


def test_the_fleet_view_draws_every_other_robot_and_its_plan_in_its_colour():
    import numpy as np

    from mission.link.view import OtherRobot
    from tests.tui.test_map import colour, tiny_view
    from tui.widgets.map_panel import FLEET, ROBOT, map_pixels

    v = tiny_view()
    v.fleet = ["r1", "r2", "r3"]
    v.others = [OtherRobot("r3", (1.6, 0.2, 0.0), np.array([[1.6, 0.2], [1.6, 0.9]])), OtherRobot("r2", (3.0, 0.5, 0.0))]
    cv = map_pixels(v, 60, 20)
    assert colour(cv, 0.4 - 0.1, 0.5 + 0.1) == ROBOT  # the robot shown, as ever
    assert colour(cv, 1.6 - 0.1, 0.2 + 0.1) == FLEET[2]  # r3's footprint, r3's colour
    assert colour(cv, 1.6, 0.75) == FLEET[2]  # and its plan
    assert colour(cv, 3.0 - 0.1, 0.5 + 0.1) == FLEET[1]  # r2, outside the room: the window still fits it
