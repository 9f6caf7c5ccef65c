"""The arm calibration in the console's command palette: each entry asks the robot
``arm_calibrate`` with its action and the answer lands in the log, a refusal in a notification."""
from __future__ import annotations

import asyncio

from tests.tui.fakes import Recorder, idle_view
from tui.app import make_app
from tui.calibration import lines

COMMITTED = {"phase": "idle", "joints": ["elbow", "wrist"], "note": "committed: 1 of 2 offsets written",
             "outcomes": [{"joint": "elbow", "status": "written", "offset": -4, "detail": ""},
                          {"joint": "wrist", "status": "noisy", "offset": None, "detail": "spread 7.1 counts > 3"}]}


class Robot(Recorder):
    def __init__(self, refusal=None):
        super().__init__()
        self.asked, self.refusal = [], refusal

    def ask(self, command, /, **args):
        self.asked.append((command, args))
        return (None, self.refusal) if self.refusal else (COMMITTED, None)


def run_palette(robot, entry: str) -> list[str]:
    said, notes = [], []

    async def go():
        app = make_app(idle_view, robot)
        async with app.run_test(size=(160, 48)) as pilot:
            app.main.log_panel.say = said.append
            app.notify = lambda message, **kw: notes.append(message)
            await pilot.press("ctrl+p")
            await pilot.pause()
            for ch in entry:
                await pilot.press(ch if ch != " " else "space")
            await pilot.pause(0.3)
            await pilot.press("enter")
            await app.workers.wait_for_complete()
            await pilot.pause()

    asyncio.run(go())
    return said + notes


def test_a_palette_entry_asks_the_robot_and_logs_the_answer():
    robot = Robot()
    shown = run_palette(robot, "arm calibration: commit")
    assert robot.asked == [("arm_calibrate", {"action": "commit"})]
    assert shown == lines(COMMITTED)
    assert shown[2] == "  wrist: noisy (spread 7.1 counts > 3)" and shown[1] == "  elbow: written -4 counts"


def test_a_refusal_is_told():
    shown = run_palette(Robot(refusal="arm_calibrate: arm calibration is hardware only"), "arm calibration: start")
    assert any("hardware only" in s for s in shown)
