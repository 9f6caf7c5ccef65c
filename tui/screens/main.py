"""The main screen: status on top, map left, mission tree and pots right, camera and log below,
the keys in the footer. It only lays the panels out and hands each the view; the panels decide
what changed."""
from __future__ import annotations

from textual.app import ComposeResult
from textual.containers import Horizontal, Vertical
from textual.screen import Screen

from mission.link.view import RobotView
from tui.keys import KEY_SECTIONS
from tui.widgets.camera_panel import CameraPanel
from tui.widgets.key_bar import KeyBar
from tui.widgets.log_panel import LogPanel
from tui.widgets.map_panel import MapPanel
from tui.widgets.mission_tree import MissionTree
from tui.widgets.pots_table import PotsTable
from tui.widgets.status_bar import StatusBar

CAMERA_HINT = "no snapshot yet: f = front camera, w = wrist camera"


class MainScreen(Screen):
    def __init__(self, camera_hint: str = CAMERA_HINT, key_sections=KEY_SECTIONS):
        super().__init__()
        self.key_sections = key_sections
        self.status_bar, self.map_panel = StatusBar(id="status"), MapPanel(id="map")
        self.mission_tree, self.pots_table = MissionTree(id="tree"), PotsTable(id="pots")
        self.camera_panel = CameraPanel(camera_hint, id="camera")
        self.log_panel = LogPanel(id="log", max_lines=500, wrap=False)

    def compose(self) -> ComposeResult:
        yield self.status_bar
        with Horizontal(id="middle"):
            yield self.map_panel
            with Vertical(id="side"):
                yield self.mission_tree
                yield self.pots_table
        with Horizontal(id="bottom"):
            yield self.camera_panel
            yield self.log_panel
        yield KeyBar(self.key_sections, id="keys")  # ctrl+p still opens the palette (its "keys" lists every binding)

    def on_mount(self) -> None:
        for widget, title in ((self.mission_tree, "mission"), (self.camera_panel, "camera"), (self.log_panel, "log")):
            widget.border_title = title  # the map and the pots title themselves (what they show)

    def show(self, view: RobotView) -> None:
        for panel in (self.status_bar, self.map_panel, self.mission_tree, self.pots_table, self.log_panel):
            panel.show(view)
        self.map_panel.set_class(view.estop_engaged, "-estop")
