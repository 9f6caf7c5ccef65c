"""The status bar: battery, e-stop, who drives the wheels, navigation, mission, controllers, link."""
from __future__ import annotations

import math

from rich.text import Text
from textual.widgets import Static

from mission.link.view import RobotView


def status_text(v: RobotView) -> Text:
    t = Text(no_wrap=True, overflow="ellipsis")
    t.append(f" {v.robot or 'robot'} ", "bold reverse")
    t.append("  ")
    if not v.connected:
        t.append(" NO LINK ", "bold white on red")
        t.append("  ")
    if math.isfinite(v.battery_percentage):
        style = "bold white on red" if v.battery_low else "green"
        amps = f" {v.battery_current:.1f} A" if math.isfinite(v.battery_current) else ""
        t.append(f"battery {v.battery_percentage:.0f}% {v.battery_voltage:.2f} V{amps}{' LOW' if v.battery_low else ''}", style)
    else:
        t.append("battery ?", "dim")
    t.append("  ")
    if v.estop_engaged:
        t.append(" E-STOP ENGAGED ", "bold white on red")
    elif v.estop_latched:
        t.append(" e-stop released: r to resume ", "bold black on yellow")
    else:
        t.append("e-stop clear", "green")
    t.append(f"  wheels: {v.mux_source}")
    nav = v.nav_state + (f" ({v.nav_reason})" if v.nav_reason and v.nav_state in ("failed", "canceled") else "")
    t.append(f"  nav: {nav}")
    mission = v.mission_state + (f" {v.mission_name}" if v.mission_name else "")
    if v.mission_state == "done" and v.mission_outcome:
        mission += f": {v.mission_outcome}"
    t.append(f"  mission: {mission}", "bold" if v.mission_state in ("running", "paused", "estop") else "")
    if v.mission_step and v.mission_state != "done":
        t.append(f" / {v.mission_step}", "italic")
    down = [name for name, state in v.controllers.items() if state != "active"]
    t.append("  controllers: ")
    if not v.controllers:
        t.append("?", "dim")
    elif down:
        t.append(", ".join(f"{n} {v.controllers[n]}" for n in down), "bold red")
    else:
        t.append("all active", "green")
    return t


class StatusBar(Static):
    def show(self, view: RobotView) -> None:
        self.update(status_text(view))
