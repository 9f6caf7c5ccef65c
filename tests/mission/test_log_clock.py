"""The log's times are on one clock: a line the link stamps at runtime t says t, not the
mission's own time (issue 19: a resume logged at 90.2 s said "resumed at t=45.4")."""
from __future__ import annotations

import logging
import re

from hw.config import EStopConfig
from hw.estop import EStopBridge
from mission.link.telemetry import LinkLogHandler
from mission.patrol.holds import MissionHolds
from tests.fixtures import FakeButton


class Posts:
    """An outbox that keeps what is posted."""

    def __init__(self):
        self.lines: list[str] = []

    def post(self, key, payload):
        self.lines.append(payload().decode())


def test_pause_and_resume_say_the_time_the_log_line_is_stamped_with():
    clock = [60.0]
    holds = MissionHolds(EStopBridge(EStopConfig(engaged_level=1), FakeButton(0), logging.getLogger("test")),
                         lambda: clock[0], 44.8)  # the mission started 44.8 s into the runtime
    posts = Posts()
    handler = LinkLogHandler(posts, "mirte", lambda: clock[0])
    logger = logging.getLogger("mission.patrol.holds")
    logger.addHandler(handler)
    level, logger.level = logger.level, logging.INFO
    disabled, logger.disabled = logger.disabled, False
    muted = logging.root.manager.disable  # a library run earlier in this process may have muted logging
    logging.disable(logging.NOTSET)
    try:
        holds.pause()
        clock[0] = 90.2
        assert holds.resume() is None
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)
        logger.disabled = disabled
        logging.disable(muted)
    assert len(posts.lines) == 2
    for line in posts.lines:
        stamp = float(line.split()[0])
        said = float(re.search(r"at t=([\d.]+)", line).group(1))
        assert said == stamp  # one clock
    assert posts.lines[1].split()[0] == "90.2" and "resumed" in posts.lines[1]
    assert holds.estop_events == []  # the report's times (from the mission's start) are not the log's


def test_the_report_keeps_counting_from_the_mission_start():
    clock = [100.0]
    button = FakeButton(0)
    holds = MissionHolds(EStopBridge(EStopConfig(engaged_level=1), button, logging.getLogger("test")),
                         lambda: clock[0], 60.0)
    button.level, clock[0] = 1, 130.0
    holds.estop()
    assert holds.estop_events == [{"t": 70.0, "engaged": True}]
