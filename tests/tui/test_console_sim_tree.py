"""The mission tree panel on the real patrol's tree (py_trees' own rendering, over the link from
a sim runtime): folded to the running branch and scrolled to it, the battery-low branch one
line; paused, the branch in progress stays open and in view."""
from __future__ import annotations

import asyncio
import re
import time

import pytest

from mission.link.client import LinkClient
from tests.link.sim_service import TOKEN, runtime  # noqa: F401  (runtime: the fixture)
from tests.tui.fakes import until
from tui.app import make_app
from tui.widgets.mission_tree import running_line

pytestmark = pytest.mark.slow
ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")


def plain(app) -> list[str]:
    return [ANSI.sub("", line) for line in app.main.mission_tree.shown]


def test_the_real_tree_shows_its_running_branch_also_paused(runtime):
    client = LinkClient(runtime.endpoint, "mirte", clock=time.monotonic, token=TOKEN, timeout=10.0)
    seen = {}

    async def go():
        app = make_app(client.view, client)
        async with app.run_test(size=(160, 48)) as pilot:
            assert await until(pilot, lambda: client.view().connected, 10)
            await pilot.press("m")
            await app.workers.wait_for_complete()

            def approaching():
                return any(re.search(r"approach P\d+.*\[\*\]", line) for line in plain(app))

            assert await until(pilot, approaching, 60)
            await pilot.pause(0.3)
            tree = app.main.mission_tree
            lines = plain(app)
            step = running_line("\n".join(lines))  # the deepest running line
            seen["running"] = (lines, tree.in_view(step), len(client.view().tree.splitlines()))
            await pilot.press("p")
            await app.workers.wait_for_complete()
            assert await until(pilot, lambda: any("operator pause [*]" in s and "paused" in s for s in plain(app)), 10)
            await pilot.pause(0.3)
            lines = plain(app)
            pot = next(i for i, line in enumerate(lines) if re.search(r"approach P\d+", line))
            seen["paused"] = (lines, tree.in_view(pot))
            await pilot.press("r")
            await app.workers.wait_for_complete()

    try:
        asyncio.run(go())
    finally:
        client.close()
    lines, in_view, whole = seen["running"]
    text = "\n".join(lines)
    assert len(lines) < whole  # folded
    assert in_view and re.search(r"approach P\d+ \[\*\]", lines[running_line(text)])
    assert re.search(r"battery low \[", text) and "battery low?" not in text  # the idle branch: one line
    paused, pot_in_view = seen["paused"]
    assert pot_in_view and "battery low?" not in "\n".join(paused)
