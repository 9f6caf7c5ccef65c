"""The console reading the patrol history of a real sim runtime over the link (``lupin serve``'s
service and link server, its SQLite history holding two earlier patrols of mission ``m``): the
pot table's history while the robot is idle and once it patrols ``m`` again, and ``i`` on the
pot in progress showing its timeline from the robot's database."""
from __future__ import annotations

import asyncio
import json
import threading
import time
from datetime import timedelta

import pytest

from mission.history.store import open_history
from mission.link.client import LinkClient
from tests.history.conftest import T0, add_patrol, obs
from tests.tui.fakes import until
from tui.app import make_app
from tui.screens.timeline import Timeline

pytestmark = pytest.mark.slow

TOKEN = "tok"


def test_the_console_reads_a_served_history(tmp_path):
    from mission.jobs.serve import run_service
    from mission.jobs.sim_serve import start_sim_service
    from mission.link.server import LinkServer, free_endpoint
    from mission.patrol.mission_file import mission_from_world
    from mission.runtime.config import LupinConfig, with_overrides
    from sim.world import load_default_world

    history = open_history(str(tmp_path / "h.db"))
    add_patrol(history, [obs("P01", bug=True), obs("P02")], started=T0)
    add_patrol(history, [obs("P01", bug=True), obs("P02", blooms=4)], started=T0 + timedelta(hours=6))
    # a loaded machine (two real-time sims on two cores) can keep the loop from a command for 2 s
    config = with_overrides(LupinConfig(), {"sim": {"realtime": True}, "link": {"command_timeout": 10.0}})
    world = load_default_world()
    service = start_sim_service(world, config, tmp_path / "runs", time.perf_counter, history=history)
    endpoint = free_endpoint()
    server = LinkServer(service, config.link, TOKEN, endpoint)
    stop = threading.Event()
    thread = threading.Thread(target=run_service, args=(service, stop, server.close), daemon=True)
    thread.start()
    client = LinkClient(endpoint, "mirte", clock=time.monotonic, token=TOKEN, timeout=10.0)
    mission = mission_from_world(world).model_copy(update={"name": "m"})
    mission = json.loads(json.dumps(mission.model_copy(update={"pots": mission.pots[:2]}).model_dump()))
    seen = {}

    async def go():
        app = make_app(client.view, client)
        table = app.main.pots_table
        async with app.run_test(size=(160, 48)) as pilot:
            assert await until(pilot, lambda: client.view().connected)
            # idle: the latest mission's last two patrols (no rows on the table yet)
            assert await until(pilot, lambda: table.marks is not None)
            seen["idle"] = {p: (m.since, m.streak_text) for p, m in table.marks.items()}
            assert client.send("mission_start", mission=mission) is None
            assert await until(pilot, lambda: client.view().mission_state == "running" and len(table.rows) == 2)
            await app.workers.wait_for_complete()
            await pilot.pause()
            seen["streaks"] = {r[0]: r[-1] for r in table.rows}
            table.select("P01")  # picked: the pot in progress may already be P02 on a loaded machine
            await pilot.press("i")
            assert await until(pilot, lambda: isinstance(app.screen, Timeline) and app.screen.entries is not None)
            seen["timeline"] = (app.screen.pot, [(e["patrol"], e["bug"]) for e in app.screen.entries])
            await pilot.press("escape")
            await pilot.pause()
            seen["closed"] = type(app.screen).__name__

    try:
        asyncio.run(go())
        client.send("mission_abort")
    finally:
        client.close()
        stop.set()
        thread.join(30)
    assert seen["idle"] == {"P01": ("", "x2"), "P02": ("bloom 1→4", "")}
    assert seen["streaks"] == {"P01": "x2", "P02": ""}  # patrol 3 has not judged P01 yet: the streak stays
    pot, entries = seen["timeline"]
    assert pot == "P01" and entries[:2] == [(1, True), (2, True)]  # from the robot's database, oldest first
    assert seen["closed"] == "MainScreen"
