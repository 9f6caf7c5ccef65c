"""The operator console on a fleet: the robot console over a ``FleetLink``, keys 1-9 pick the
robot shown and ``E`` stops every robot (spec/fleet.md, "The console").

Everything else is the robot console (``tui.app``): the panels draw the robot shown, commands go
to it, ``space`` stops it. The fleet's stop goes out on a worker like every command and the log
says which robots answered it; a robot that does not answer is named, so the operator knows
which one to walk to.
"""
from __future__ import annotations

from textual import work

from tui.app import ConsoleApp
from tui.keys import FLEET_BINDINGS, FLEET_KEY_SECTIONS
from tui.messages import CommandRefused
from tui.screens.main import MainScreen


class FleetConsoleApp(ConsoleApp):
    BINDINGS = FLEET_BINDINGS

    def __init__(self, fleet):
        """``fleet``: a ``mission.link.fleet_link.FleetLink`` (or a test's twin: ``view``,
        ``send``, ``snapshot``, ``robots``, ``select``, ``stop_fleet``)."""
        super().__init__(fleet.view, fleet)
        self.fleet = fleet
        self.main = MainScreen(key_sections=FLEET_KEY_SECTIONS)

    def action_robot(self, index: int) -> None:
        shown = self.fleet.select(index)
        if shown is None:
            self.notify(f"no robot {index + 1}: {len(self.fleet.robots())} up", timeout=3)
            return
        self.main.log_panel.say(f"showing {shown}")
        self.redraw()

    def action_stop_fleet(self) -> None:
        self._stop_fleet()

    @work(thread=True, group="fleet-stop")
    def _stop_fleet(self) -> None:
        up = self.fleet.robots()
        try:
            stopped = self.fleet.stop_fleet()
        except Exception as exc:  # a broken link must not take the console down
            self.post_message(CommandRefused("stop_fleet", f"fleet e-stop: {type(exc).__name__}: {exc}"))
            return
        silent = [r for r in up if r not in stopped]
        if silent:
            self.post_message(CommandRefused("stop_fleet", f"fleet e-stop: no answer from {', '.join(silent)}"))
        self.call_from_thread(self.main.log_panel.say, f"fleet e-stop: {', '.join(stopped) or 'no robot'} stopped")
