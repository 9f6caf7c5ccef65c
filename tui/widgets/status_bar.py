"""The status bar: the link, battery, e-stop, who drives the wheels, navigation, mission and
controllers, most urgent first. Each is one chip; the chips wrap onto a second line rather than
being cut off on a narrow terminal."""
from __future__ import annotations

import math

from rich.text import Text
from textual.widgets import Static

from mission.link.view import RobotView

ALARM = "bold white on red"


def status_chips(v: RobotView) -> list[Text]:
    chips = [Text(f" {v.robot or 'robot'} ", "bold reverse")]
    if v.fleet:  # a fleet console: every robot up, by the key that shows it
        chips.append(Text("  ".join(f"{i + 1} {r}" for i, r in enumerate(v.fleet[:9])), "bold"))
    chips.append(Text("link ok", "green") if v.connected else Text(" NO LINK ", ALARM))
    if v.estop_engaged:
        chips.append(Text(" E-STOP ENGAGED (kept across a restart) " if v.estop_why else " E-STOP ENGAGED ", ALARM))
    elif v.estop_latched:
        chips.append(Text(" e-stop released: r to resume ", "bold black on yellow"))
    else:
        chips.append(Text("e-stop clear", "green"))
    if math.isfinite(v.battery_percentage):
        amps = f" {v.battery_current:.1f} A" if math.isfinite(v.battery_current) else ""
        volts = f" {v.battery_voltage:.2f} V" if math.isfinite(v.battery_voltage) else ""
        battery = f"battery {v.battery_percentage:.0f}%{volts}{amps}"
        chips.append(Text(f" {battery} LOW ", ALARM) if v.battery_low else Text(battery, "green"))
    else:
        chips.append(Text("battery ?", "dim"))
    if math.isfinite(v.charge):
        dock = f", {v.charge_at_dock:.0%} at the dock" if math.isfinite(v.charge_at_dock) else ""
        chips.append(Text(f"charge {v.charge:.0%}{dock}"))
    if v.heading_home:
        chips.append(Text(f" heading home: {v.heading_home} ", "bold black on yellow"))
    mission = Text(f"mission: {v.mission_state}" + (f" {v.mission_name}" if v.mission_name else ""),
                   "bold" if v.mission_state in ("running", "paused", "estop") else "")
    if v.mission_state == "done" and v.mission_outcome:
        mission.append(f": {v.mission_outcome}")
    elif v.mission_step:
        mission.append(f" / {v.mission_step}", "italic")
    chips.append(mission)
    nav = Text(f"nav: {v.nav_state}")
    if v.nav_reason:
        nav.append(f" ({v.nav_reason})", "bold red" if v.nav_state == "failed" else "")
    chips.append(nav)
    chips.append(Text(f"wheels: {v.mux_source}"))
    if not v.monitor_enabled:  # nobody may miss that nothing stands between the twist and a person
        chips.append(Text(" COLLISION MONITOR OFF ", ALARM))
    if v.monitor_fault:  # the lidar cannot be trusted: the base will not drive
        chips.append(Text(f" {v.monitor_fault.replace('_', ' ')} ", ALARM))
    if v.monitor_action != "none":  # the collision monitor is holding the base back, and why
        near = f" {v.monitor_nearest:.2f} m" if math.isfinite(v.monitor_nearest) else ""
        chips.append(Text(f" {v.monitor_action}{near} ", "bold white on red" if v.monitor_action in ("stop", "blind")
                          else "bold black on yellow"))
    down = [f"{name} {state}" for name, state in v.controllers.items() if state != "active"]
    controllers = Text("controllers: ")
    if not v.controllers:
        controllers.append("?", "dim")
    elif down:
        controllers.append(", ".join(down), "bold red")
    else:
        controllers.append("all active", "green")
    chips.append(controllers)
    return chips


def status_text(v: RobotView, width: int = 0) -> Text:
    """The chips two spaces apart, a new line where the next would pass ``width`` (0: never)."""
    t, used = Text(no_wrap=True, overflow="ellipsis"), 0
    for chip in status_chips(v):
        if used:
            if width and used + 2 + chip.cell_len > width:
                t.append("\n")
                used = 0
            else:
                t.append("  ")
                used += 2
        t.append_text(chip)
        used += chip.cell_len
    return t


class StatusBar(Static):
    def __init__(self, **kw):
        super().__init__(**kw)
        self._shown: Text | None = None
        self._view: RobotView | None = None

    def on_resize(self) -> None:
        if self._view is not None:  # re-wrap for the new width, once this layout pass is over
            self.call_after_refresh(self.show, self._view)

    def show(self, view: RobotView) -> None:
        self._view = view
        text = status_text(view, self.content_size.width)
        if text != self._shown:
            self._shown = text
            self.update(text)
