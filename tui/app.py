"""The operator console: one Textual app over a ``RobotView`` and a ``Commands`` object.

``make_app(view_source, commands)`` is the one factory (the CLI, the benchmarks and the tests
use it). The app polls ``view_source()`` at ``POLL_HZ`` and hands the view to the main screen,
whose panels redraw what changed; it acts only through ``commands`` (the link client, or a
test's fake). The keys are in :mod:`tui.keys`.

Nothing here waits on the robot. Commands go out on worker threads and come back as typed
messages (:mod:`tui.messages`): a refusal is shown in the log and as a notification. The
operator's commands go out one at a time in the order pressed, a stop first (``InOrder``). Teleop has
one worker and a one-slot mailbox: a twist pressed while the previous one is still on its way
replaces any twist still waiting, so a slow link never builds a backlog that would keep the
robot driving after the key is let go, and a run of the same teleop refusal is told once.

The robot's patrol history (``commands.history``: the link client's; a ``Commands`` without it
has none) is asked on a worker of its own, one question at a time: when the patrol starts or
ends or a pot is finished, and every ``HISTORY_S`` seconds. Its answers fill the pot table's
history columns (:mod:`tui.history_marks`); ``i`` reads the selected pot's timeline the same way.
"""
from __future__ import annotations

import threading
from collections import deque
from typing import Any, Callable

from textual import work
from textual.app import App

from mission.link.view import Commands, RobotView
from tui import calibration
from tui.keys import BINDINGS, DRIVE
from tui.history_marks import PEST_PATROLS, pot_marks
from tui.messages import CommandRefused, HistoryRead, SnapshotTaken, TimelineRead
from tui.screens.confirm import Confirm
from tui.screens.main import MainScreen
from tui.screens.timeline import Timeline

POLL_HZ = 10.0
HISTORY_S = 15.0
"""How often the history is asked again besides a patrol's start, end and finished pots: rows are
written off the robot's thread, and may land just after the pot's status came."""
NO_HISTORY = "this link cannot read the robot's history"


class Mailbox:
    """Items between the UI and one worker: ``put`` keeps an item (``_keep``) and says whether a
    worker must be started; ``take`` returns the next (``_next``), or None and marks the worker
    gone (both under one lock, so no item is ever stranded)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._draining = False

    def put(self, item: Any) -> bool:
        with self._lock:
            self._keep(item)
            start, self._draining = not self._draining, True
            return start

    def take(self) -> Any:
        with self._lock:
            item = self._next()
            if item is None:
                self._draining = False
            return item

    def _keep(self, item: Any) -> None:
        raise NotImplementedError

    def _next(self) -> Any:
        raise NotImplementedError


class Latest(Mailbox):
    """A one-slot mailbox: ``put`` replaces what waits."""

    def __init__(self) -> None:
        super().__init__()
        self._item: Any = None

    def _keep(self, item: Any) -> None:
        self._item = item

    def _next(self) -> Any:
        item, self._item = self._item, None
        return item


class InOrder(Mailbox):
    """The console's commands, (command, args), delivered in the order they were pressed.

    A worker per command let them race: a release pressed just after a stop could reach the
    robot first and be undone by it, and worse, a stop pressed just after a release could land
    first and be undone by the release (the robot free while the operator's last press was
    STOP). One worker keeps the order. A stop (``estop`` engaged) goes to the front and takes any
    release still waiting with it: the last press of the stop key wins, and a stop never waits
    behind more than the one command already on its way."""

    def __init__(self) -> None:
        super().__init__()
        self._items: deque[tuple[str, dict[str, Any]]] = deque()

    def _keep(self, item: tuple[str, dict[str, Any]]) -> None:
        command, args = item
        if command == "estop" and args.get("engaged"):
            self._items = deque(i for i in self._items if i[0] != "estop")
            self._items.appendleft(item)
        else:
            self._items.append(item)

    def _next(self) -> tuple[str, dict[str, Any]] | None:
        return self._items.popleft() if self._items else None


class ConsoleApp(App):
    CSS_PATH = "console.tcss"
    TITLE = "Lupin console"
    BINDINGS = BINDINGS

    def __init__(self, view_source: Callable[[], RobotView], commands: Commands):
        super().__init__()
        self.view_source, self.commands = view_source, commands
        self.view = RobotView()
        self.main = MainScreen()
        self._twists = Latest()
        self._orders = InOrder()
        self._teleop_refusal: str | None = None
        self._history_asks = Latest()
        self._history_moment: tuple | None = None

    def get_default_screen(self) -> MainScreen:
        return self.main

    def on_mount(self) -> None:
        self.redraw()
        self.set_interval(1.0 / POLL_HZ, self.redraw)
        if self.history_source is not None:
            self.set_interval(HISTORY_S, self.ask_history)

    def redraw(self) -> None:
        """Pull the latest view and show it (also under the clear-map question)."""
        self.view = self.view_source()
        self.main.show(self.view)
        moment = (self.view.mission_name, self.view.mission_state,
                  sum(p.status in ("inspected", "failed", "skipped") for p in self.view.pots))
        if moment != self._history_moment:  # a patrol started or ended, a pot was finished
            self._history_moment = moment
            self.ask_history()

    # --- the patrol history (a worker thread, one question at a time) -------------------------
    @property
    def history_source(self):
        """``commands.history`` (query, **args) -> (answer, error), or None: no history here."""
        return getattr(self.commands, "history", None)

    def ask_history(self) -> None:
        """Ask the history again for the pot table (never waits: at most one question out)."""
        if self.history_source is not None and self._history_asks.put((self.view.mission_name or None,)):
            self._read_history()

    def _ask(self, query: str, **args: Any) -> tuple[dict | None, str | None]:
        try:
            return self.history_source(query, **args)
        except Exception as exc:  # a broken link must not take the console down
            return None, f"history: {type(exc).__name__}: {exc}"

    @work(thread=True, group="history")
    def _read_history(self) -> None:
        while (ask := self._history_asks.take()) is not None:
            mission, = ask
            args = {"mission": mission} if mission else {}
            changes, _ = self._ask("changes", **args)
            pests, _ = self._ask("pests", last=PEST_PATROLS, **args)
            self.post_message(HistoryRead(changes, pests))

    def on_history_read(self, message: HistoryRead) -> None:
        if message.changes is None and message.pests is None:  # no answer: what was shown stays
            return
        table = self.main.pots_table
        running = self.view.mission_state in ("running", "paused", "estop")
        not_yet = [p.id for p in self.view.pots if p.status in ("pending", "active")] if running else []
        table.set_marks(pot_marks(message.changes, message.pests, table.marks, not_yet))

    @work(thread=True, group="history-timeline")
    def _read_timeline(self, pot: str) -> None:
        if self.history_source is None:
            self.post_message(TimelineRead(pot, None, NO_HISTORY))
            return
        answer, error = self._ask("pot", pot=pot)
        self.post_message(TimelineRead(pot, answer, error))

    def on_timeline_read(self, message: TimelineRead) -> None:
        for screen in self.screen_stack:
            if isinstance(screen, Timeline) and screen.pot == message.pot:
                screen.show_answer(message.answer, message.error)

    # --- the arm's calibration (the command palette: tui.calibration) -------------------------
    def get_system_commands(self, screen):
        yield from super().get_system_commands(screen)
        if getattr(self.commands, "ask", None) is not None:
            yield from calibration.commands(self.calibrate)

    @work(thread=True, group="calibration")
    def calibrate(self, action: str) -> None:
        try:
            answer, refused = self.commands.ask("arm_calibrate", action=action)
        except Exception as exc:  # a broken link must not take the console down
            answer, refused = None, f"arm_calibrate: {type(exc).__name__}: {exc}"
        if refused:
            self.post_message(CommandRefused("arm_calibrate", refused))
            return
        for line in calibration.lines(answer):
            self.call_from_thread(self.main.log_panel.say, line)

    # --- talking to the robot (worker threads) ---------------------------------------------
    def _deliver(self, command: str, args: dict[str, Any]) -> str | None:
        try:
            return self.commands.send(command, **args)
        except Exception as exc:  # a broken link must not take the console (and its e-stop) down
            return f"{command}: {type(exc).__name__}: {exc}"

    def send(self, command: str, /, **args: Any) -> None:
        """Send a command in its turn (``InOrder``); a refusal comes back as a message."""
        if self._orders.put((command, args)):
            self._send_in_order()

    @work(thread=True, group="commands")
    def _send_in_order(self) -> None:
        while (order := self._orders.take()) is not None:
            command, args = order
            refused = self._deliver(command, args)
            if refused:
                self.post_message(CommandRefused(command, refused))

    @work(thread=True, group="teleop")
    def _drive(self) -> None:
        while (twist := self._twists.take()) is not None:
            vx, vy, wz = twist
            refused = self._deliver("teleop", {"vx": vx, "vy": vy, "wz": wz})
            if refused != self._teleop_refusal:
                self._teleop_refusal = refused
                if refused:
                    self.post_message(CommandRefused("teleop", refused))

    @work(thread=True, group="snapshots", exclusive=True)
    def _snapshot(self, camera: str) -> None:
        try:
            jpeg = self.commands.snapshot(camera)
        except Exception as exc:
            self.post_message(CommandRefused("snapshot", f"snapshot: {type(exc).__name__}: {exc}"))
            jpeg = None
        self.post_message(SnapshotTaken(camera, jpeg))

    def on_command_refused(self, message: CommandRefused) -> None:
        self.main.log_panel.say(message.reason)
        self.notify(message.reason, title="refused", severity="error", timeout=4)

    def on_snapshot_taken(self, message: SnapshotTaken) -> None:
        self.main.camera_panel.show_jpeg(message.camera, message.jpeg)

    # --- actions (tui.keys binds them) ------------------------------------------------------
    def action_drive(self, key: str) -> None:
        if self._twists.put(DRIVE[key]):
            self._drive()

    def action_estop(self, engage: bool) -> None:
        self.send("estop", engaged=engage)

    def action_send(self, command: str) -> None:
        self.send(command)

    def action_preset(self, name: str) -> None:
        self.send("arm_preset", name=name)

    def action_gripper(self, action: str) -> None:
        self.send("gripper", action=action)

    def action_snapshot(self, camera: str) -> None:
        self._snapshot(camera)

    # the view keys: what the console shows, nothing sent
    def action_zoom(self, steps: int) -> None:
        self.main.map_panel.zoom(steps)

    def action_pan(self, dx: int, dy: int) -> None:
        self.main.map_panel.pan(dx, dy)

    def action_follow(self) -> None:
        self.main.map_panel.toggle_follow()

    def action_fit(self) -> None:
        self.main.map_panel.fit()

    def action_anomalies(self) -> None:
        self.main.pots_table.toggle_anomalies()

    def action_select_pot(self, step: int) -> None:
        self.main.pots_table.select_next(step)

    def action_timeline(self) -> None:
        pot = self.main.pots_table.selected_pot()
        if pot is None:
            self.notify("no pot to show: the mission has no pots", timeout=3)
            return
        self.push_screen(Timeline(pot))
        self._read_timeline(pot)

    def action_clear_map(self) -> None:
        def answered(yes: bool | None) -> None:
            if yes:
                self.send("clear_map")

        self.push_screen(Confirm("Clear the map? SLAM starts over from here."), answered)


def make_app(view_source: Callable[[], RobotView], commands: Commands) -> ConsoleApp:
    """The console over ``view_source()`` (polled, never waited on) acting through ``commands``."""
    return ConsoleApp(view_source, commands)
