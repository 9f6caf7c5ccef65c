"""Hand-made views and a recording Commands for the console's tests."""
from __future__ import annotations

import cv2
import numpy as np

from mission.link.view import GridView, PotView, RobotView


class Recorder:
    """A ``Commands`` that records what it was sent and refuses what it is told to."""

    def __init__(self, refuse: dict[str, str] | None = None):
        self.sent: list[tuple[str, dict]] = []
        self.snapshots: list[str] = []
        self.refuse = refuse or {}

    def send(self, command: str, /, **args) -> str | None:
        self.sent.append((command, args))
        return self.refuse.get(command)

    def snapshot(self, camera: str) -> bytes | None:
        self.snapshots.append(camera)
        img = np.zeros((48, 64, 3), np.uint8)
        img[:, :32] = (0, 0, 255)  # red left half (BGR)
        return cv2.imencode(".jpg", img)[1].tobytes()


def idle_view() -> RobotView:
    return RobotView(robot="mirte", t=3.0, connected=True, battery_voltage=12.6, battery_percentage=38.5,
                     controllers={"pid_wheels_controller": "active", "mirte_base_controller": "active"})


def grid(n: int = 120) -> GridView:
    g = np.full((n, n), -1, np.int8)
    g[10:n - 10, 10:n - 10] = 0
    g[10, 10:n - 10] = g[n - 11, 10:n - 10] = 100
    g[10:n - 10, 10] = g[10:n - 10, n - 11] = 100
    return GridView(g, 0.05, -1.0, -1.0)


def patrolling_view() -> RobotView:
    v = idle_view()
    v.t, v.pose, v.mux_source, v.nav_state = 41.2, (2.0, 0.5, 0.3), "auto", "following"
    v.mission_state, v.mission_name, v.mission_step = "running", "default-patrol", "approach P03"
    v.grid, v.plan = grid(), np.array([[2.0, 0.5], [3.0, 0.8], [3.5, 1.5]])
    c = np.zeros((120, 120), np.int8)
    c[40:60, 40:60] = 80
    v.costmap = GridView(c, 0.05, -1.0, -1.0)
    v.pots = [PotView("P01", 1.0, 1.0, "inspected", 1, "red", 1), PotView("P02", 2.0, 1.0, "inspected", 2, "white", 2, ["bug"]),
              PotView("P03", 3.0, 1.0, "active"), PotView("P04", 4.0, 1.0, "pending")]
    v.tree = "{-} Lupin patrol [*]\n    --> approach P03 [*]"
    v.log = ["  40.0 I patrol default-patrol started (4 pots)"]
    return v


def estopped_view() -> RobotView:
    v = patrolling_view()
    v.estop_engaged, v.estop_latched, v.mux_source, v.mission_state, v.mission_step = True, True, "estop", "estop", "e-stop engaged"
    return v
