"""The operator console: one Textual app over a ``RobotView`` and a ``Commands`` object.

``make_app(view_source, commands)`` is the one factory (the CLI and the tests use it): the app
polls ``view_source()`` at ``POLL_HZ`` and redraws, and acts only through ``commands`` (the
link client, or a test's fake). Commands go out on worker threads, so a slow link never freezes
the screen; a refused one is shown in the log and as a notification.

Keys (the footer shows them): arrows drive on the ``manual`` source (up/down forward and back,
left/right strafe), q / e turn; terminals have no key-up, so each press and auto-repeat sends a
twist and letting go sends nothing: the mux times the source out after 0.5 s. space = soft
e-stop (again: release), r = resume, m = start the mission, p = pause, c = clear the map (asks
first), 1-6 = arm presets, o / g = gripper open / close, f / w = front / wrist snapshot.
"""
from __future__ import annotations

from typing import Callable

from textual import work
from textual.app import App, ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.widgets import Footer

from arm.presets import PRESETS
from mission.link.view import Commands, RobotView
from tui.confirm import Confirm
from tui.widgets.camera_panel import CameraPanel
from tui.widgets.log_panel import LogPanel
from tui.widgets.map_panel import MapPanel
from tui.widgets.mission_panel import MissionTree, PotsTable
from tui.widgets.status_bar import StatusBar

POLL_HZ = 10.0
SPEED, TURN = 0.2, 0.5
"""Teleop speeds: m/s (forward, strafe) and rad/s."""
DRIVE = {"up": (SPEED, 0.0, 0.0), "down": (-SPEED, 0.0, 0.0), "left": (0.0, SPEED, 0.0),
         "right": (0.0, -SPEED, 0.0), "q": (0.0, 0.0, TURN), "e": (0.0, 0.0, -TURN)}
ARM_PRESETS = list(PRESETS)[:6]


class ConsoleApp(App):
    CSS_PATH = "console.tcss"
    TITLE = "Lupin console"
    BINDINGS = [
        *[Binding(k, f"drive('{k}')", label, show=show, priority=True) for k, label, show in (
            ("up", "fwd", True), ("down", "back", False), ("left", "strafe", True), ("right", "strafe", False),
            ("q", "turn", True), ("e", "turn", False))],
        Binding("space", "estop", "e-stop"),
        Binding("r", "send('resume')", "resume"),
        Binding("m", "send('mission_start')", "mission"),
        Binding("p", "send('pause')", "pause"),
        Binding("c", "clear_map", "clear map"),
        *[Binding(str(i + 1), f"preset('{name}')", name, show=i == 0) for i, name in enumerate(ARM_PRESETS)],
        Binding("o", "gripper('open')", "open"),
        Binding("g", "gripper('close')", "grip"),
        Binding("f", "snapshot('front')", "front cam"),
        Binding("w", "snapshot('wrist')", "wrist cam", show=False),
        Binding("ctrl+q", "quit", "quit"),
    ]

    def __init__(self, view_source: Callable[[], RobotView], commands: Commands):
        super().__init__()
        self.view_source, self.commands = view_source, commands
        self.view = view_source()

    def compose(self) -> ComposeResult:
        yield StatusBar(id="status")
        with Horizontal(id="main"):
            yield MapPanel(id="map")
            with Vertical(id="side"):
                yield MissionTree(id="tree")
                yield PotsTable(id="pots")
        with Horizontal(id="bottom"):
            yield CameraPanel("no snapshot yet: f = front, w = wrist", id="camera")
            yield LogPanel(id="log", max_lines=500, wrap=False)
        yield Footer()

    def on_mount(self) -> None:
        # Held, not queried on each redraw: a question on top (clear map?) is another screen.
        self.panels = [self.query_one(w) for w in (StatusBar, MapPanel, MissionTree, PotsTable, LogPanel)]
        self.camera, self.log_panel = self.query_one(CameraPanel), self.query_one(LogPanel)
        for widget, title in ((self.panels[1], "map"), (self.camera, "camera"), (self.log_panel, "log")):
            widget.border_title = title
        self.redraw()
        self.set_interval(1.0 / POLL_HZ, self.redraw)

    def redraw(self) -> None:
        """Pull the latest view and show it everywhere."""
        self.view = v = self.view_source()
        for widget in self.panels:
            widget.show(v)

    # --- actions -------------------------------------------------------------------------
    @work(thread=True, group="commands")
    def command(self, command: str, /, **args) -> None:
        refused = self.commands.send(command, **args)
        if refused:
            self.call_from_thread(self.refused, refused)

    def refused(self, reason: str) -> None:
        self.log_panel.say(reason)
        self.notify(reason, severity="error", timeout=4)

    def action_send(self, name: str) -> None:
        self.command(name)

    def action_drive(self, key: str) -> None:
        vx, vy, wz = DRIVE[key]
        self.command("teleop", vx=vx, vy=vy, wz=wz)

    def action_estop(self) -> None:
        self.command("estop", engaged=not self.view.estop_engaged)

    def action_preset(self, name: str) -> None:
        self.command("arm_preset", name=name)

    def action_gripper(self, action: str) -> None:
        self.command("gripper", action=action)

    def action_clear_map(self) -> None:
        def answered(yes: bool | None) -> None:
            if yes:
                self.command("clear_map")

        self.push_screen(Confirm("Clear the map? SLAM starts over from here."), answered)

    @work(thread=True, group="snapshots", exclusive=True)
    def action_snapshot(self, camera: str) -> None:
        jpeg = self.commands.snapshot(camera)
        self.call_from_thread(self.camera.show_jpeg, camera, jpeg)


def make_app(view_source: Callable[[], RobotView], commands: Commands) -> ConsoleApp:
    return ConsoleApp(view_source, commands)
